#include "io/text_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/limits.h"

namespace clothsim::io {

std::string read_text_file(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, std::string("cannot read file (") + std::strerror(errno) + "); expected " + what);
  // The size is checked before the file is read into memory; a folder or a pipe reports no size and is read.
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size > limits::max_input_file_bytes)
    throw Error(path, "file of " + std::to_string(size) + " bytes; expected at most " +
                          std::to_string(limits::max_input_file_bytes) + " (docs/errors.md)");
  // A regular file is read straight into a string of its size: a stream copy would grow by doubling and hold a
  // large mesh's text up to three times over.
  if (!ec) {
    std::string text(size, '\0');
    in.read(text.data(), std::streamsize(size));
    if (in.bad() || std::size_t(in.gcount()) != size) throw Error(path, "read failed; expected " + what);
    return text;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw Error(path, "read failed; expected " + what);
  return std::move(ss).str();
}

}  // namespace clothsim::io

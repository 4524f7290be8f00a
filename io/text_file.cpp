#include "io/text_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <zlib.h>

#include "core/error.h"
#include "core/limits.h"

namespace clothsim::io {

namespace {

bool gzip_name(const std::string& path) { return path.size() > 3 && path.compare(path.size() - 3, 3, ".gz") == 0; }

// A gzip file (zlib's gz reader) decompressed whole; the size limit applies to the decompressed text.
std::string read_gzip_file(const std::string& path, const std::string& what) {
  gzFile in = gzopen(path.c_str(), "rb");
  if (!in) throw Error(path, std::string("cannot read file (") + std::strerror(errno) + "); expected " + what);
  std::string text;
  char buffer[1 << 16];
  for (;;) {
    const int got = gzread(in, buffer, sizeof buffer);
    int code = Z_OK;
    const std::string why = gzerror(in, &code);
    // A truncated stream ends with Z_BUF_ERROR after the bytes it had; corrupt data with Z_DATA_ERROR.
    if (got < 0 || (code != Z_OK && code != Z_STREAM_END)) {
      gzclose(in);
      throw Error(path, "not a readable gzip file (" + why + "); expected " + what + ", gzip-compressed");
    }
    if (got == 0) break;
    text.append(buffer, std::size_t(got));
    if (text.size() > limits::max_input_file_bytes) {
      gzclose(in);
      throw Error(path, "decompresses to over " + std::to_string(limits::max_input_file_bytes) +
                            " bytes; expected at most that (docs/errors.md)");
    }
  }
  gzclose(in);
  return text;
}

}  // namespace

std::string read_text_file(const std::string& path, const std::string& what) {
  if (gzip_name(path)) return read_gzip_file(path, what);
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

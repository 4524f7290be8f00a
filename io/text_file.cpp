#include "io/text_file.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <zlib.h>

#include "core/error.h"
#include "core/limits.h"

namespace clothsim::io {

namespace {

// A folder, FIFO or device is refused before it is opened: opening a FIFO with no writer blocks for ever and
// /dev/zero never ends, and the size limit can only be checked on a regular file (stat(2)).
void require_regular_file(const std::string& path, const std::string& what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw Error(path, std::string("cannot read file (") + std::strerror(errno) + "); expected " + what);
  if (S_ISREG(st.st_mode)) return;
  const char* kind = S_ISDIR(st.st_mode)    ? "a folder"
                     : S_ISFIFO(st.st_mode) ? "a FIFO (named pipe)"
                     : S_ISCHR(st.st_mode)  ? "a character device"
                     : S_ISBLK(st.st_mode)  ? "a block device"
                     : S_ISSOCK(st.st_mode) ? "a socket"
                                            : "not a regular file";
  throw Error(path, std::string("is ") + kind + ", not a regular file; expected " + what);
}

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
  require_regular_file(path, what);
  if (gzip_name(path)) return read_gzip_file(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, std::string("cannot read file (") + std::strerror(errno) + "); expected " + what);
  // The size is checked before the file is read into memory.
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size > limits::max_input_file_bytes)
    throw Error(path, "file of " + std::to_string(size) + " bytes; expected at most " +
                          std::to_string(limits::max_input_file_bytes) + " (docs/errors.md)");
  if (ec) throw Error(path, "cannot read file (" + ec.message() + "); expected " + what);
  // Read straight into a string of the file's size: a stream copy would grow by doubling and hold a large
  // mesh's text up to three times over.
  std::string text(size, '\0');
  in.read(text.data(), std::streamsize(size));
  if (in.bad() || std::size_t(in.gcount()) != size) throw Error(path, "read failed; expected " + what);
  return text;
}

}  // namespace clothsim::io

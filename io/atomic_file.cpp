#include "io/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/error.h"

namespace clothsim::io {

void write_file_atomic(const std::string& path, std::string_view content) {
  write_file_atomic(path, [&](const PieceWriter& write) { write(content); });
}

void write_file_atomic(const std::string& path, const std::function<void(const PieceWriter&)>& produce) {
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw Error(path, std::string("cannot create file (") + std::strerror(errno) + "); expected a writable folder");
  bool wrote = true;
  int saved = 0;
  try {
    produce([&](std::string_view piece) {
      if (wrote && std::fwrite(piece.data(), 1, piece.size(), f) != piece.size()) {
        wrote = false;  // later pieces are dropped; the failure is reported once produce is done
        saved = errno;
      }
    });
  } catch (...) {
    std::fclose(f);
    std::remove(tmp.c_str());
    throw;
  }
  const bool flushed = std::fflush(f) == 0;
  if (!flushed && wrote) saved = errno;
  const bool closed = std::fclose(f) == 0;
  if (!closed && wrote && flushed) saved = errno;
  if (!wrote || !flushed || !closed) {
    std::remove(tmp.c_str());
    throw Error(path, std::string("write failed (") + std::strerror(saved) + "); earlier files are complete");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    saved = errno;
    std::remove(tmp.c_str());
    throw Error(path, std::string("cannot rename temporary file into place (") + std::strerror(saved) + ")");
  }
}

void ensure_writable_dir(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw Error(dir, "cannot create output folder (" + (ec ? ec.message() : std::string("not a folder")) +
                         "); expected a writable folder");
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw Error(dir, std::string("output folder is not writable (") + std::strerror(errno) + ")");
}

}  // namespace clothsim::io

#include "io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/error.h"

namespace clothsim::io {
namespace {

// Opens an existing FIFO or device for writing. O_NONBLOCK makes a FIFO nobody reads an error instead of a
// wait for ever (open(2), ENXIO); the flag is cleared before writing so a slow reader is waited for.
std::FILE* open_special(const std::string& path) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0)
    throw Error(path, std::string("cannot open for writing (") + std::strerror(errno) +
                          "); expected a regular file path, or a FIFO with a reader");
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  std::FILE* f = ::fdopen(fd, "wb");
  if (!f) ::close(fd);
  return f;
}

std::string temporary_path(const std::string& path) { return path + ".tmp" + std::to_string(::getpid()); }

}  // namespace

void write_file_atomic(const std::string& path, std::string_view content) {
  write_file_atomic(path, [&](const PieceWriter& write) { write(content); });
}

void write_file_atomic(const std::string& path, const std::function<void(const PieceWriter&)>& produce) {
  // Only a regular file (or nothing) is replaced by rename: renaming over a FIFO or device node would replace
  // the node itself, so those are written in place (a stream has no partial file to protect anyway).
  struct stat st {};
  const bool special = ::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode);
  if (special && S_ISDIR(st.st_mode)) throw Error(path, "is a folder; expected a file path");
  const std::string tmp = special ? path : temporary_path(path);
  std::FILE* f = special ? open_special(path) : std::fopen(tmp.c_str(), "wb");
  if (!f) throw Error(path, std::string("cannot create file (") + std::strerror(errno) + "); expected a writable folder");
  const auto discard = [&] {
    if (!special) std::remove(tmp.c_str());
  };
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
    discard();
    throw;
  }
  const bool flushed = std::fflush(f) == 0;
  if (!flushed && wrote) saved = errno;
  const bool closed = std::fclose(f) == 0;
  if (!closed && wrote && flushed) saved = errno;
  if (!wrote || !flushed || !closed) {
    discard();
    throw Error(path, std::string("write failed (") + std::strerror(saved) + "); earlier files are complete");
  }
  if (!special && std::rename(tmp.c_str(), path.c_str()) != 0) {
    saved = errno;
    std::remove(tmp.c_str());
    throw Error(path, std::string("cannot rename temporary file into place (") + std::strerror(saved) + ")");
  }
}

void check_output_file(const std::string& path) {
  if (path.empty()) throw Error("", "empty output file name; expected a file path");
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    if (S_ISDIR(st.st_mode)) throw Error(path, "is a folder; expected a file path");
    return;  // a FIFO or device: written in place when the run ends
  }
  // The temporary file the final write will use is created and removed: this finds a missing or read-only
  // folder, a name too long and a full disk's inode table before any simulation time is spent.
  const std::string tmp = temporary_path(path);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0)
    throw Error(path, std::string("cannot create file (") + std::strerror(errno) + "); expected a writable folder");
  ::close(fd);
  ::unlink(tmp.c_str());
}

int remove_stale_temporaries(const std::string& dir, const std::string& prefix) {
  int removed = 0;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir.empty() ? "." : dir, ec)) {
    const std::string name = e.path().filename().string();
    const auto at = name.rfind(".tmp");
    if (name.rfind(prefix, 0) != 0 || at == std::string::npos || at == 0 || at + 4 == name.size() ||
        name.find_first_not_of("0123456789", at + 4) != std::string::npos || name.size() - at > 14)
      continue;
    // A process of that id still running may be writing it (kill(2) with signal 0 only checks existence).
    const long pid = std::stol(name.substr(at + 4));
    if (pid == ::getpid() || (::kill(pid_t(pid), 0) != 0 && errno == ESRCH)) removed += std::remove(e.path().c_str()) == 0;
  }
  return removed;
}

std::string normalised_path(const std::string& path) {
  std::error_code ec;
  const auto p = std::filesystem::weakly_canonical(std::filesystem::absolute(path, ec), ec);
  return ec ? std::filesystem::path(path).lexically_normal().string() : p.string();
}

void ensure_writable_dir(const std::string& dir) {
  if (dir.empty()) throw Error("", "empty output folder name; expected a folder path");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir, ec))
    throw Error(dir, "cannot create output folder (" + (ec ? ec.message() : std::string("not a folder")) +
                         "); expected a writable folder");
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw Error(dir, std::string("output folder is not writable (") + std::strerror(errno) + ")");
}

}  // namespace clothsim::io

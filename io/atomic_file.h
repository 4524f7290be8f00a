#pragma once
// Output written to a temporary name beside the target and renamed over it once complete, so a killed run
// or a full disk never leaves a partial file under the final name.
#include <functional>
#include <string>
#include <string_view>

namespace clothsim::io {

// Writes `content` to `path` atomically; throws Error(path, ...) when any write, flush or rename fails.
void write_file_atomic(const std::string& path, std::string_view content);

// The same for content made in pieces: produce(write) calls write(piece) for each piece in order, so a large
// file is never held whole in memory. When produce throws, the temporary file is removed and the error passes on.
using PieceWriter = std::function<void(std::string_view)>;
void write_file_atomic(const std::string& path, const std::function<void(const PieceWriter&)>& produce);

// Creates `dir` (and parents) and checks a file can be written in it; throws Error(dir, ...) otherwise.
void ensure_writable_dir(const std::string& dir);

}  // namespace clothsim::io

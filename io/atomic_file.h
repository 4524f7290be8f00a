#pragma once
// Output written to a temporary name beside the target and renamed over it once complete, so a killed run
// or a full disk never leaves a partial file under the final name.
#include <string>
#include <string_view>

namespace clothsim::io {

// Writes `content` to `path` atomically; throws Error(path, ...) when any write, flush or rename fails.
void write_file_atomic(const std::string& path, std::string_view content);

// Creates `dir` (and parents) and checks a file can be written in it; throws Error(dir, ...) otherwise.
void ensure_writable_dir(const std::string& dir);

}  // namespace clothsim::io

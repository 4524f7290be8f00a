#pragma once
// Output written to a temporary name beside the target (<name>.tmp<pid>) and renamed over it once complete, so
// a killed run or a full disk never leaves a partial file under the final name. A target that exists and is not
// a regular file (a FIFO, a device) is written in place instead: a rename would replace the node itself.
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

// Checks before a run that `path` can be written: a folder is refused, an existing FIFO or device is accepted,
// otherwise the temporary file is created and removed. Throws Error(path, ...) naming what is wrong.
void check_output_file(const std::string& path);

// Removes <prefix>*.tmp<pid> files in `dir` left by a process that no longer runs (a killed write): a later run
// writing the same names cleans them. Returns how many were removed. docs/errors.md states the rule.
int remove_stale_temporaries(const std::string& dir, const std::string& prefix);

// `path` made absolute, with "." and ".." and symbolic links resolved as far as it exists
// (std::filesystem::weakly_canonical): two spellings of one output file compare equal.
std::string normalised_path(const std::string& path);

// Creates `dir` (and parents) and checks a file can be written in it; throws Error(dir, ...) otherwise.
void ensure_writable_dir(const std::string& dir);

}  // namespace clothsim::io

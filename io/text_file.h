#pragma once
#include <string>

namespace clothsim::io {

// The whole file as text; throws Error(path, "cannot read ...; expected <what>") when it cannot be opened, and
// refuses anything but a regular file (a folder, FIFO or device) before opening it.
// A name ending in .gz is decompressed (gzip, through zlib), so OBJ sequences stored compressed read as they are.
std::string read_text_file(const std::string& path, const std::string& what);

}  // namespace clothsim::io

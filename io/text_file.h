#pragma once
#include <string>

namespace clothsim::io {

// The whole file as text; throws Error(path, "cannot read ...; expected <what>") when it cannot be opened.
std::string read_text_file(const std::string& path, const std::string& what);

}  // namespace clothsim::io

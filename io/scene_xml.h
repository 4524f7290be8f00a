#pragma once
#include <string>

#include "core/scene_desc.h"

namespace clothsim::io {

// Reads a scene file (pugixml) into a SceneDesc; relative paths become paths relative to the scene's folder.
// Strict: an unknown element or attribute (a typo), a malformed or out-of-range value, or a missing required
// one throws Error with the file, the line and what was expected. docs/scene-format.md describes the format.
SceneDesc read_scene(const std::string& path);
// The same for a scene's text already read from `path` (a file is read once: it may be a pipe's only copy).
SceneDesc parse_scene(const std::string& path, const std::string& text);

}  // namespace clothsim::io

#pragma once
// The output paths of `clothsim run`, all checked before the first step so a bad one costs no simulation time
// and leaves no frame behind: one folder per cloth, the --stats file, the checkpoints.
#include <string>
#include <vector>

#include "core/scene_desc.h"

namespace clothsim::cli {

// The folder of each cloth (--out when given, else its saveDir). Throws Error when two cloths would write the
// same files (paths compared normalised), a folder cannot be made or written, or `stats` (when not empty)
// cannot be written; removes temporaries a killed earlier run left under the names this run writes.
std::vector<std::string> prepare_run_outputs(const SceneDesc& scene, const std::string* out,
                                             const std::string* stats);

}  // namespace clothsim::cli

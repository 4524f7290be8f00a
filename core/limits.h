#pragma once
// Sizes beyond which an input is refused before anything is allocated for it, so a hostile or corrupted file
// fails with a clear error (exit code 2) instead of exhausting memory. docs/errors.md lists them.
#include <cstdint>

namespace clothsim::limits {

inline constexpr std::uint64_t max_input_file_bytes = std::uint64_t{1} << 31;  // 2 GiB: scene, OBJ, list files
inline constexpr std::int64_t max_mesh_vertices = std::int64_t{1} << 24;       // 16,777,216 per mesh or grid
inline constexpr std::int64_t max_mesh_triangles = std::int64_t{1} << 25;      // 33,554,432 per mesh
inline constexpr std::int64_t max_image_pixels = std::int64_t{1} << 28;        // 16384 x 16384 per image map
inline constexpr std::int64_t max_steps_per_frame = 1000000;                   // 1/(fps * timestep), rounded up
// Largest magnitude of a number in a scene file (stiffness, scale, positions, ...): products of a few such
// numbers stay finite in double precision, so a typo such as stiffness="1e308" is bad input, not a NaN.
inline constexpr double max_scene_number = 1e12;

}  // namespace clothsim::limits

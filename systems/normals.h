#pragma once
#include <span>

#include "core/model.h"

namespace clothsim {

// Unit vertex normals: the area-weighted sum of the incident triangles' normals, gathered per vertex over the
// CSR of incident triangles (each cross product is recomputed from each corner: no scatter, no race).
void eval_normals(const Model& model, std::span<const Vec3> x, std::span<Vec3> normal);

}  // namespace clothsim

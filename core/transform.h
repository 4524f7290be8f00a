#pragma once
#include "core/scene_desc.h"

namespace clothsim {

// p' = R (s * p) + t with R = Rz Ry Rx: scale first, then rotate about X, then Y, then Z, then translate.
Mat3 rotation_xyz_degrees(const Vec3& degrees);
Vec3 apply_transform(const TransformDesc& t, const Vec3& p);

}  // namespace clothsim

#include "core/transform.h"

#include <Eigen/Geometry>
#include <numbers>

namespace clothsim {

Mat3 rotation_xyz_degrees(const Vec3& degrees) {
  const Vec3 r = degrees * (std::numbers::pi / 180.0);
  using Eigen::AngleAxisd;
  return (AngleAxisd(r.z(), Eigen::Vector3d::UnitZ()) * AngleAxisd(r.y(), Eigen::Vector3d::UnitY()) *
          AngleAxisd(r.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Vec3 apply_transform(const TransformDesc& t, const Vec3& p) {
  return rotation_xyz_degrees(t.rotate) * p.cwiseProduct(t.scale) + t.translate;
}

}  // namespace clothsim

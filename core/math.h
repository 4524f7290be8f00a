#pragma once
// Scalar and small-vector aliases. Real is double: the accuracy studies need it.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace clothsim {

using Real = double;
using Vec2 = Eigen::Matrix<Real, 2, 1, Eigen::DontAlign>;
using Vec3 = Eigen::Matrix<Real, 3, 1, Eigen::DontAlign>;
using Mat3 = Eigen::Matrix<Real, 3, 3, Eigen::DontAlign>;
using Index = std::int32_t;  // particle, spring and triangle indices: 2^31 is far beyond any mesh we load

// A symmetric 3x3 matrix as its six distinct entries (xx, yy, zz, xy, xz, yz): 48 bytes instead of Mat3's 72,
// for the per-spring blocks that every CG product of the implicit step streams (docs/performance.md).
struct Sym3 {
  Real xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;

  // a must be symmetric; its lower triangle is read.
  static Sym3 from(const Mat3& a) { return {a(0, 0), a(1, 1), a(2, 2), a(1, 0), a(2, 0), a(2, 1)}; }
  Mat3 full() const {
    Mat3 a;
    a << xx, xy, xz, xy, yy, yz, xz, yz, zz;
    return a;
  }
  Sym3& operator+=(const Sym3& o) {
    xx += o.xx, yy += o.yy, zz += o.zz, xy += o.xy, xz += o.xz, yz += o.yz;
    return *this;
  }
  Vec3 operator*(const Vec3& p) const {
    return {xx * p.x() + xy * p.y() + xz * p.z(), xy * p.x() + yy * p.y() + yz * p.z(),
            xz * p.x() + yz * p.y() + zz * p.z()};
  }
};

}  // namespace clothsim

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

// A symmetric 3x3 matrix as its six distinct entries (xx, yy, zz, xy, xz, yz): 48 bytes instead of Mat3's 72
// in double. The per-spring and multigrid edge blocks that every CG product of the implicit step streams are kept
// in float (Sym3f, 24 bytes) unless the solve asks for more (core/model.h, kFloatBlockTolerance): a block's
// rounding is a relative 6e-8 of that spring's own term, a backward error inside CG's tolerance whatever the
// matrix's conditioning, and the products and sums that read them work in double (docs/performance.md,
// "Implicit workspace memory").
template <class T>
struct Sym3Of {
  T xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;

  // a must be symmetric; its lower triangle is read.
  static Sym3Of from(const Mat3& a) {
    return {T(a(0, 0)), T(a(1, 1)), T(a(2, 2)), T(a(1, 0)), T(a(2, 0)), T(a(2, 1))};
  }
  template <class U>
  static Sym3Of cast(const Sym3Of<U>& o) {
    return {T(o.xx), T(o.yy), T(o.zz), T(o.xy), T(o.xz), T(o.yz)};
  }
  Mat3 full() const {
    Mat3 a;
    a << Real(xx), Real(xy), Real(xz), Real(xy), Real(yy), Real(yz), Real(xz), Real(yz), Real(zz);
    return a;
  }
  template <class U>
  Sym3Of& operator+=(const Sym3Of<U>& o) {
    xx += T(o.xx), yy += T(o.yy), zz += T(o.zz), xy += T(o.xy), xz += T(o.xz), yz += T(o.yz);
    return *this;
  }
  Vec3 operator*(const Vec3& p) const {
    const Real a = xx, b = yy, c = zz, d = xy, e = xz, f = yz;
    return {a * p.x() + d * p.y() + e * p.z(), d * p.x() + b * p.y() + f * p.z(), e * p.x() + f * p.y() + c * p.z()};
  }
};
using Sym3 = Sym3Of<Real>;
using Sym3f = Sym3Of<float>;

}  // namespace clothsim

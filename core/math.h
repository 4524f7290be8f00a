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

}  // namespace clothsim

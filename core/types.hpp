// Common numeric types. SI units everywhere (m, kg, s).
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace chainmail {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;
using Mat3 = Eigen::Matrix3d;
using Positions = Eigen::Matrix3Xd;     // (3, n) m
using Orientations = Eigen::Matrix4Xd;  // (4, n) quaternion (w, x, y, z), local ring frame -> world

// 1 / sqrt(n2) for a squared norm n2. Near 1 (a unit vector or quaternion after a small turn:
// every contact correction renormalises one) the series to third order is exact to rounding (it
// errs by 35/128 (n2 - 1)^4 < 3e-17) and needs neither a square root nor a division, whose latency
// is much of the contact loops' time
inline double inverse_norm(double n2) {
  const double e = n2 - 1.0;
  return std::abs(e) < 1e-4 ? 1.0 + e * (-0.5 + e * (0.375 - 0.3125 * e)) : 1.0 / std::sqrt(n2);
}

// ring index pair; the smaller index first
struct RingPair {
  int a;
  int b;
  friend bool operator==(const RingPair&, const RingPair&) = default;
};

}  // namespace chainmail

// Common numeric types. SI units everywhere (m, kg, s).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace chainmail {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;
using Mat3 = Eigen::Matrix3d;
using Positions = Eigen::Matrix3Xd;     // (3, n) m
using Orientations = Eigen::Matrix4Xd;  // (4, n) quaternion (w, x, y, z), local ring frame -> world

// ring index pair; the smaller index first
struct RingPair {
  int a;
  int b;
  friend bool operator==(const RingPair&, const RingPair&) = default;
};

}  // namespace chainmail

#include "core/plausible/neighbour_frame.hpp"

namespace chainmail {

bool neighbour_frame(const Weave& weave, const Positions& x, int r, Eigen::Matrix3d& frame) {
  const auto& next = weave.neighbours[r];  // (i-1,j), (i+1,j), (i,j-1), (i,j+1); -1 none
  auto span = [&](int low, int high) -> Vec3 {
    return x.col(high >= 0 ? high : r) - x.col(low >= 0 ? low : r);
  };
  const Vec3 along = span(next[0], next[1]), across = span(next[2], next[3]);  // m
  const Vec3 normal = along.cross(across);                                     // m^2
  const double scale = along.squaredNorm() * across.squaredNorm();             // m^4
  if (!(normal.squaredNorm() > 1e-12 * scale)) return false;  // also where a span is 0
  frame.col(0) = along.normalized();
  frame.col(2) = normal.normalized();
  frame.col(1) = frame.col(2).cross(frame.col(0));
  return true;
}

Positions rest_axes_in_frame(const Weave& weave) {
  const int n = weave.size();
  Positions axes = Positions::Zero(3, n);
  const Orientations& o = weave.rest_orientation;
  Eigen::Matrix3d frame;
  for (int r = 0; r < n; ++r) {
    if (!neighbour_frame(weave, weave.rest_position, r, frame)) continue;
    const Vec3 axis = Quat(o(0, r), o(1, r), o(2, r), o(3, r)) * Vec3::UnitY();
    axes.col(r) = frame.transpose() * axis;
  }
  return axes;
}

Vec3 axis_in_frame(const Weave& weave, const Positions& rest_in_frame, const Positions& x, int r) {
  Eigen::Matrix3d frame;
  if (!neighbour_frame(weave, x, r, frame)) return Vec3::Zero();
  return frame * rest_in_frame.col(r);
}

}  // namespace chainmail

// Stateless position constraints (in the manner of PositionBasedDynamics): each function reads
// positions and inverse masses and writes corrections; the caller owns the state.
#pragma once

#include <cmath>

#include "core/types.hpp"

namespace chainmail {

// Whether `apart` reaches past `range` along `way` (any length, not normalised) by a margin no
// rounding of the normalised test apart . way / |way| >= range can cross: true only where that
// test holds. No square root, no division.
inline bool clear_along(const Vec3& apart, const Vec3& way, double range) {
  const double way2 = way.squaredNorm();  // m^2
  if (way2 < 1e-24) return false;
  const double along = apart.dot(way);  // m^2
  return along > 0.0 && along * along > (1.0 + 1e-9) * (range * range) * way2;
}

// Provot edge constraint: keep |p1 - p0| within [min_length, max_length].
// The correction is shared by inverse mass; pinned ends (w = 0) do not move.
// Returns the violation |length - bound| (m), 0 when the edge already satisfies the bounds
// (corrections untouched): the sweeps' residual without a second square root.
inline double solve_edge_constraint(const Vec3& p0, double w0, const Vec3& p1, double w1,
                                    double min_length, double max_length, Vec3& corr0,
                                    Vec3& corr1) {
  const Vec3 d = p1 - p0;
  const double length2 = d.squaredNorm();
  // most edges are within bounds: decide on squared lengths, no square root
  if (length2 <= max_length * max_length && length2 >= min_length * min_length) return 0.0;
  const double w = w0 + w1;
  if (w == 0.0 || length2 < 1e-30) return 0.0;
  const double length = std::sqrt(length2);
  // decided on the squares, as above: an edge a rounding above its maximum can have a square root
  // equal to it, and compared there would be pulled in to its minimum
  const double target = length2 > max_length * max_length ? max_length : min_length;
  // one division: error / (length * w) scales d to each end's share of the correction
  const double scale = (length - target) / (length * w);  // > 0 stretched, < 0 compressed
  corr0 = (w0 * scale) * d;
  corr1 = -(w1 * scale) * d;
  return std::abs(length - target);
}

// long-range attachment: keep p within max_distance of a fixed anchor (a pin); only p moves.
// Returns the violation length - max_distance (m), 0 when it already is (correction untouched).
inline double solve_attachment_constraint(const Vec3& p, const Vec3& anchor, double max_distance,
                                          Vec3& corr) {
  const Vec3 d = p - anchor;
  const double length2 = d.squaredNorm();
  if (length2 <= max_distance * max_distance) return 0.0;
  const double length = std::sqrt(length2);
  corr = ((max_distance - length) / length) * d;
  return length - max_distance;
}

// the way a push between two rings goes when their rims slide toward their faces (rings pressed
// together rim to rim, or leaning coins pressed together along their row): unit `normal` (a to b)
// turned toward each ring's axis by `slip` of the axis's part across it, each axis signed by the
// side of the normal it points to (edge on, where the distance falls neither way, the way it
// points). A zero axis adds nothing. Unit; its dot with `normal` is at least 1 / sqrt(1 + 4 slip^2)
inline Vec3 slide_toward_faces(const Vec3& normal, const Vec3& axis_a, const Vec3& axis_b,
                               double slip) {
  Vec3 side = Vec3::Zero();
  for (const Vec3* axis : {&axis_a, &axis_b}) {
    const double along = axis->dot(normal);
    side += (along < 0.0 ? -1.0 : 1.0) * (*axis - along * normal);
  }
  return (normal + slip * side).normalized();
}

// linear repulsion between two non-neighbour rings closer than `range`: a spring of stiffness k
// pushing them apart (paper §3, after Bridson et al.); returns the force on p0 (p1 gets minus it)
inline Vec3 repulsion_force(const Vec3& p0, const Vec3& p1, double range, double stiffness) {
  const Vec3 d = p0 - p1;
  const double length = d.norm();
  if (length >= range || length < 1e-15) return Vec3::Zero();
  return (stiffness * (range - length) / length) * d;
}

}  // namespace chainmail

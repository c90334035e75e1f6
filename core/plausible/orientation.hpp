// Ring orientation from neighbour vectors (paper §4): the basis of eq. (1) and the swivel.
#pragma once

#include "core/ring.hpp"
#include "core/types.hpp"
#include "core/weave.hpp"

namespace chainmail {

// eq. (1): two neighbour directions x and z (not necessarily orthogonal) -> a right-handed
// orthonormal basis, columns (x', y, z'), with y = |z x x| the ring axis and x', z' rotated apart
// to 45 deg either side of the bisector v45 = |x + z|:  v135 = y x v45,  x' = |v45 + v135|,  z' =
// x' x y.
Mat3 orthonormal_basis_eq1(const Vec3& x, const Vec3& z);
// the same from unit x and z and the unit normal y = z x x / |z x x|
Mat3 basis_from_unit_axes(const Vec3& xn, const Vec3& zn, const Vec3& y);

// swivel angle interpolated linearly between a/c at full extension (ratio 1) and pi/2 fully
// compressed (ratio = min_ratio), ratio = mean neighbour distance / maximum link distance
double swivel_angle(double ratio, double min_ratio, double extended_angle);

// the paper's swivel at full extension, a/c (rad): the default wherever none is given
inline double paper_extended_swivel(const RingGeometry& ring) {
  return ring.wire_radius / ring.centre_radius;
}

// the swivel at full extension that leaves the most wire clearance between a ring and its grid
// neighbours when all four sit at `max_link_distance` along orthogonal axes, each swivelled the
// other way (the 4-in-1 pattern at full extension), searched over [0, pi/2] among angles that keep
// the pair linked. The paper's a/c is far smaller for common aspect ratios and leaves neighbours
// interpenetrating; this is the same interpolation with its lower end taken from the geometry.
double fitted_extended_swivel(const RingGeometry& ring, double max_link_distance);

struct OrientationSettings {
  double max_link_distance = 0.0;  // m, the model's maximum neighbour distance
  bool swivel = true;              // 4in1: swivel rings to form the weave
  double extended_angle = 0.0;     // rad, swivel at full extension; the paper's a/c when 0
  // (3, n) m, the direction the weave holds each ring from (pull_toward_pins): a 4-in-1 ring's
  // hinge turns toward it (swivel_hinge); null, or a zero column, keeps the hinge the neighbour
  // distances give
  const Positions* pull = nullptr;
  int threads = 1;  // threads of the per-ring loops (core/parallel.hpp)
};

// rad, the largest turn of a hinge from the row normal: 15 degrees, about how far the rigid
// rings of a corner-hung sheet turn theirs in the ODE reference (10 degrees on average, up to
// 25 at the top corners); a turn to the full pull (45 degrees) matches them worse
inline constexpr double kMaxHingeTurn = 0.2617993877991494;

// the hinge a 4-in-1 ring swivels about, unit, in its eq. (1) frame (neighbours near local X and
// Z, axis Y): the row normal (1, 0, -1) / sqrt(2) turned toward the in-plane direction of `pull`
// (local) by the angle between them, at most kMaxHingeTurn either way. The hinge keeps the row
// normal's side, so the weave's parity still decides which way a ring leans: the rows of 4-in-1
// cannot trade places, the load only turns them a little
Vec3 swivel_hinge(const Vec3& pull);

// orientations of every ring from the ring centres (paper §4). `orientation` holds the previous
// orientations on entry (used only where a ring lacks neighbours along a grid direction) and the
// new ones on exit.
void orient_rings(const Positions& position, const Weave& weave, const RingGeometry& ring,
                  const OrientationSettings& settings, Orientations& orientation);

// turns each ring that the centre frames leave unlinked from a neighbour (a fold: no plane holds
// links that go three ways) to the orientation nearest its own that links the most neighbours,
// searched over turns about its local X and Z axes up to 75 degrees; rings already linked to every
// neighbour are left as they are. Linked rings cannot come apart, so their orientations are the
// ones that keep them linked. Returns how many rings turned.
int keep_links(const Positions& position, const Weave& weave, const RingGeometry& ring,
               Orientations& orientation);

}  // namespace chainmail

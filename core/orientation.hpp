// Ring orientation from neighbour vectors (paper §4): the basis of eq. (1) and the swivel.
#pragma once

#include "core/ring.hpp"
#include "core/types.hpp"
#include "core/weave.hpp"

namespace chainmail {

// eq. (1): orthogonalise two neighbour directions x, z (not necessarily orthogonal) into a
// right-handed orthonormal basis (x', y, z') with y = |z x x| the ring axis.
// v45 = |x + z|, v135 = y x v45, x' = |v45 + v135| ... rotated so x' and z' sit 45 deg either side
// of v45, which keeps the basis symmetric between the two neighbour directions.
Mat3 orthonormal_basis_eq1(const Vec3& x, const Vec3& z);

// swivel angle: a/c when neighbours sit at full extension (ratio 1), pi/2 fully compressed (ratio
// at the minimum distance); linear in between. ratio = mean neighbour distance / max distance.
double swivel_angle(double distance_ratio, double min_ratio, const RingGeometry& ring);

// orientations of every ring of a sheet or chain from its centres (paper §4)
void orient_rings(const Positions& position, const Weave& weave, const RingGeometry& ring,
                  double max_link_distance, Orientations& orientation);

}  // namespace chainmail

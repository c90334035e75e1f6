// The largest centre distance of two linked rings, from the ring geometry: it depends on how the
// two rings are turned relative to the line between their centres (perpendicular rings of a chain
// reach the inner diameter, rings turned towards each other touch sooner). Exact, from the
// circle-circle distance and the linking test of core/geometry, through the same search as the
// rigid-torus model's (core/link_distance.hpp).
#pragma once

#include "core/ring.hpp"
#include "core/types.hpp"
#include "core/weave.hpp"

namespace chainmail {

// the largest centre distance d <= ID at which a ring at the origin with unit axis `first` and
// one at d * direction with unit axis `second` are linked with their tori not interpenetrating
// (centre circles at least 2a apart); 0 when no such distance exists (rings turned nearly into
// one plane, like 4-in-1 neighbours at the paper's swivel, cannot link without touching). m
double exact_max_link_distance(const RingGeometry& ring, const Vec3& first, const Vec3& second,
                               const Vec3& direction);

// the largest length of a 4-in-1 link whose rings lean by +-lean about the sheet's row normal
// (the advance direction), the link at angle alpha from the row within the sheet: the reach
// shrinks as the link turns toward the row, where the leaning rings face each other. 0 when the
// geometry gives none. m
double four_in_one_link_reach(const RingGeometry& ring, double lean, double alpha);
// rad, the angle of a 4-in-1 link from its row in the weave's rest layout (half a ring along the
// row, one row on)
double four_in_one_rest_link_angle();

// the largest link length of a weave's neighbours as the plausible model turns them at full
// extension: a chain's perpendicular rings; 4-in-1 neighbours swivelled by +-`extended_swivel`
// about their row normal, placed as the rest layout places them; 0 when the geometry gives none
// (and for a plain grid). m
double weave_max_link_distance(const Weave& weave, const RingGeometry& ring,
                               double extended_swivel);

}  // namespace chainmail

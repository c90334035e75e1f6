// Circle-circle distance, torus interpenetration and the linking test.
// A ring is described by its centre circle: centre, unit normal and radius c.
#pragma once

#include <optional>

#include "core/types.hpp"

namespace chainmail {

struct Circle {
  Vec3 centre;
  Vec3 normal;  // unit
  double radius;
};

// closed-form distance from a point to a circle (to the nearest point of the circle line)
double point_circle_distance(const Vec3& p, const Circle& circle);

// minimum distance between two circles: sample one circle, evaluate the closed-form
// point-to-circle distance, then refine every sampled local minimum by golden-section search.
// accurate to about 1e-9 relative for the default sample count. Slow: the tests' reference for
// the closed-form path (core/circle_contact), and the swivel fit's (once per model)
double circle_circle_distance(const Circle& first, const Circle& second, int samples = 64);

// the minimum distance between two circles when it is below `limit`, else nothing; cheap for
// the common far case (centre distance or samples of core/circle_contact's closed-form distance
// decide), the sampled minima refined by its Newton iteration otherwise. Torus depth of equal
// tube radius a: 2a - distance
std::optional<double> circles_closer_than(const Circle& first, const Circle& second, double limit);

// two tori of equal tube radius a interpenetrate iff their centre circles come closer than 2a;
// `tolerance` is subtracted from 2a so touching rings do not count.
// same answer as circles_closer_than(first, second, 2a - tolerance).has_value()
bool tori_interpenetrate(const Circle& first, const Circle& second, double wire_radius,
                         double tolerance);

// number of times `second` crosses the open disk bounded by `first`: 0, 1 or 2, in closed form
// (the height of a circle above a plane is a sinusoid). Robust: heights within a small band of the
// first's plane count as on it, so coplanar circles (within the band) cross nothing, a touch
// without a strict change of side is no crossing, and a crossing on the rim (within the band) is
// outside. Round-off in a rigid placement never flips the count; the band is 1e-9 of the radii
// plus a few ulps of the coordinates.
int disk_crossings(const Circle& first, const Circle& second);
// linked iff the second circle crosses the disk of the first exactly once
inline bool circles_linked(const Circle& first, const Circle& second) {
  return disk_crossings(first, second) == 1;
}

// false only where no point of the circle comes within its radius of `point`, with room for
// rounding: a circle that crosses another's open disk passes within that one's radius of its
// centre
bool circle_may_pass_within_radius(const Circle& circle, const Vec3& point);
// false only where circles_linked is false, from a few dot products and no tangent basis: within
// reach, the second reaching past the first's plane on both sides, and each passing within its
// radius of the other's centre (the second crosses the first's open disk, and linked circles cross
// each other's), each with room for rounding. A search over many candidate orientations asks it
// first
bool circles_may_link(const Circle& first, const Circle& second);

Circle ring_circle(const Vec3& centre, const Quat& orientation, double centre_radius);

}  // namespace chainmail

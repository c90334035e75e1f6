// Circle-circle distance, torus interpenetration and the linking test.
// A ring is described by its centre circle: centre, unit normal and radius c.
#pragma once

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
// accurate to about 1e-9 relative for the default sample count.
double circle_circle_distance(const Circle& first, const Circle& second, int samples = 64);

// two tori of equal tube radius a interpenetrate iff their centre circles come closer than 2a;
// `tolerance` is subtracted from 2a so touching rings do not count.
bool tori_interpenetrate(const Circle& first, const Circle& second, double wire_radius,
                         double tolerance);

// number of times `second` crosses the open disk bounded by `first`
int disk_crossings(const Circle& first, const Circle& second, int samples = 96);
// linked iff the second circle crosses the disk of the first exactly once
inline bool circles_linked(const Circle& first, const Circle& second) {
  return disk_crossings(first, second) == 1;
}

Circle ring_circle(const Vec3& centre, const Quat& orientation, double centre_radius);

}  // namespace chainmail

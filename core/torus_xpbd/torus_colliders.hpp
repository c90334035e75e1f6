// A ring against a scene collider, on the exact torus: the torus is every point within the wire
// radius a of the ring's centre circle, so it meets a collider where the centre circle comes
// within a of it, deepest where the centre circle is deepest. Planes and spheres have that point
// in closed form; boxes and cylinders are searched along the circle.
#pragma once

#include "core/circle_contact.hpp"
#include "core/scene.hpp"

namespace chainmail {

struct CirclePointContact {
  double cos_s = 1.0, sin_s = 0.0;  // angle of the point on the centre circle
  Vec3 point = Vec3::Zero();        // m, on the centre circle
  Vec3 normal = Vec3::UnitY();      // unit, out of the collider
  double distance = 0.0;  // m, signed distance of `point` from the collider's surface; the torus
                          // penetrates the collider by a - distance where that is positive
};

// the centre circle's point deepest in (or nearest to) the collider. A plane or sphere that every
// point of the circle meets alike (the ring lies flat on the plane, or is centred on the sphere's
// axis) gives angle 0. Boxes and cylinders: in closed form where a face's plane decides (a ring
// lying on a face), else the best of 16 samples refined by parabolic interpolation to 1e-5 rad
// (their distance is smooth along the circle except at edges, where the search still brackets
// the minimum).
CirclePointContact deepest_circle_point(const Collider& collider, const CircleFrame& circle);

// the same from the last deepest angle (cos_s, sin_s): for boxes and cylinders a search in the
// third of a radian either side of it (from scratch when the minimum has left that bracket)
CirclePointContact deepest_circle_point_near(const Collider& collider, const CircleFrame& circle,
                                             double cos_s, double sin_s);

// a lower bound on the signed distance of every point of the circle to the collider, cheaper than
// the deepest point: exact for planes and spheres, the tightest of the supporting planes of a
// box's faces or of a cylinder's caps and side
double circle_collider_lower_bound(const Collider& collider, const CircleFrame& circle);

// a cheap lower bound: no point of a circle of radius r around `centre` comes nearer to the
// collider than this (m)
double circle_collider_bound(const Collider& collider, const Vec3& centre, double radius);

}  // namespace chainmail

// Static colliders of a scene as signed-distance queries on points.
#pragma once

#include "core/scene.hpp"
#include "core/types.hpp"

namespace chainmail {

struct ColliderContact {
  Vec3 normal = Vec3::UnitY();  // unit, out of the collider
  double depth = 0.0;           // m, > 0 when the point (inflated by margin) is inside
};

// signed distance of p to the collider's surface (negative inside); normal points outward
double collider_distance(const Collider& collider, const Vec3& p, Vec3& normal);

// when p lies closer than `margin` to the collider (or inside), report the push-out contact
inline bool collider_contact(const Collider& collider, const Vec3& p, double margin,
                             ColliderContact& contact) {
  const double d = collider_distance(collider, p, contact.normal) - margin;
  contact.depth = -d;
  return d < 0.0;
}

}  // namespace chainmail

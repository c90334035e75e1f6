#include "core/colliders.hpp"

#include <algorithm>
#include <cmath>

namespace chainmail {

double collider_distance(const Collider& collider, const Vec3& p, Vec3& normal) {
  switch (collider.type) {
    case Collider::Type::plane: {
      normal = collider.normal;
      return (p - collider.center).dot(collider.normal);
    }
    case Collider::Type::sphere: {
      const Vec3 d = p - collider.center;
      const double r = d.norm();
      normal = r > 1e-15 ? Vec3(d / r) : Vec3::UnitY();
      return r - collider.radius;
    }
    case Collider::Type::box: {
      const Vec3 local = p - collider.center;
      const Vec3 q = local.cwiseAbs() - collider.half_extents;
      if (q.maxCoeff() <= 0.0) {
        // inside: leave through the nearest face
        int axis = 0;
        q.maxCoeff(&axis);
        normal = Vec3::Zero();
        normal[axis] = local[axis] >= 0.0 ? 1.0 : -1.0;
        return q[axis];
      }
      const Vec3 outside = q.cwiseMax(0.0);
      const Vec3 offset = outside.cwiseProduct(local.cwiseSign());
      normal = offset.normalized();
      return outside.norm();
    }
    case Collider::Type::cylinder: {
      // axis along world y, capped
      const Vec3 local = p - collider.center;
      const Eigen::Vector2d radial(local.x(), local.z());
      const double r = radial.norm();
      const double dr = r - collider.radius;
      const double dy = std::abs(local.y()) - collider.half_height;
      const Vec3 radial_dir = r > 1e-15 ? Vec3(local.x() / r, 0.0, local.z() / r) : Vec3::UnitX();
      const Vec3 cap_dir(0.0, local.y() >= 0.0 ? 1.0 : -1.0, 0.0);
      if (dr <= 0.0 && dy <= 0.0) {
        normal = dr > dy ? radial_dir : cap_dir;
        return std::max(dr, dy);
      }
      if (dr > 0.0 && dy > 0.0) {
        const Vec3 offset = dr * radial_dir + dy * cap_dir;
        normal = offset.normalized();
        return offset.norm();
      }
      normal = dr > 0.0 ? radial_dir : cap_dir;
      return std::max(dr, dy);
    }
  }
  normal = Vec3::UnitY();
  return 1e300;
}

}  // namespace chainmail

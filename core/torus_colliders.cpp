#include "core/torus_colliders.hpp"

#include <cmath>
#include <numbers>

#include "core/colliders.hpp"

namespace chainmail {
namespace {

CirclePointContact at_angle(const Collider& collider, const CircleFrame& circle, double c,
                            double s) {
  CirclePointContact out;
  out.cos_s = c, out.sin_s = s;
  out.point = circle.at(c, s);
  out.distance = collider_distance(collider, out.point, out.normal);
  return out;
}

// the circle's point farthest along -direction: its in-plane part, normalised (angle 0 when the
// direction is normal to the circle's plane)
void lowest_angle(const CircleFrame& circle, const Vec3& direction, double& c, double& s) {
  const double dx = direction.dot(circle.x), dz = direction.dot(circle.z);
  const double norm = std::hypot(dx, dz);
  if (norm <= 1e-12 * direction.norm()) {
    c = 1.0, s = 0.0;
    return;
  }
  c = -dx / norm, s = -dz / norm;
}

// boxes and cylinders: 16 samples, then golden-section search between the best one's neighbours
CirclePointContact searched(const Collider& collider, const CircleFrame& circle) {
  constexpr int kSamples = 16;
  const double step = 2.0 * std::numbers::pi / kSamples;
  int best = 0;
  double best_distance = 1e300;
  Vec3 normal;
  for (int k = 0; k < kSamples; ++k) {
    const double d = collider_distance(collider, circle.at(std::cos(k * step), std::sin(k * step)),
                                       normal);
    if (d < best_distance) best_distance = d, best = k;
  }
  const auto f = [&](double angle) {
    return collider_distance(collider, circle.at(std::cos(angle), std::sin(angle)), normal);
  };
  const double inv_phi = 0.5 * (std::sqrt(5.0) - 1.0);
  double lo = (best - 1) * step, hi = (best + 1) * step;
  double x1 = hi - inv_phi * (hi - lo), x2 = lo + inv_phi * (hi - lo);
  double f1 = f(x1), f2 = f(x2);
  while (hi - lo > 1e-9) {
    if (f1 < f2) {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - inv_phi * (hi - lo), f1 = f(x1);
    } else {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + inv_phi * (hi - lo), f2 = f(x2);
    }
  }
  const double angle = f1 < f2 ? x1 : x2;
  CirclePointContact out = at_angle(collider, circle, std::cos(angle), std::sin(angle));
  // the sampled best when the bracket held no lower point (a corner of the distance)
  if (best_distance < out.distance)
    out = at_angle(collider, circle, std::cos(best * step), std::sin(best * step));
  return out;
}

}  // namespace

CirclePointContact deepest_circle_point(const Collider& collider, const CircleFrame& circle) {
  double c = 1.0, s = 0.0;
  switch (collider.type) {
    case Collider::Type::plane:
      // the height over the plane is a sinusoid along the circle: lowest against the normal
      lowest_angle(circle, collider.normal, c, s);
      return at_angle(collider, circle, c, s);
    case Collider::Type::sphere:
      // the circle's point nearest to the sphere's centre: towards it in the circle's plane
      lowest_angle(circle, circle.centre - collider.center, c, s);
      return at_angle(collider, circle, c, s);
    case Collider::Type::box:
    case Collider::Type::cylinder:
      return searched(collider, circle);
  }
  return at_angle(collider, circle, c, s);
}

double circle_collider_bound(const Collider& collider, const Vec3& centre, double radius) {
  // the distance to a surface changes by at most the distance moved
  Vec3 normal;
  return collider_distance(collider, centre, normal) - radius;
}

}  // namespace chainmail

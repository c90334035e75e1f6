#include "core/torus_xpbd/torus_colliders.hpp"

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

// the minimum of f in [lo, hi] around its best known point x (f values flo, fx, fhi): successive
// parabolic interpolation, a golden-section step where a parabola will not do; done when the
// bracket or a parabolic step is below 1e-7 rad (at an edge's kink the bracket closes on the
// minimum)
template <class F>
double bracketed_minimum(const F& f, double lo, double x, double hi, double flo, double fx,
                         double fhi) {
  constexpr double kTolerance = 1e-7;  // rad
  for (int it = 0; it < 40 && hi - lo > kTolerance; ++it) {
    const double p = (x - lo) * (x - lo) * (fx - fhi) - (x - hi) * (x - hi) * (fx - flo);
    const double q = (x - lo) * (fx - fhi) - (x - hi) * (fx - flo);
    double u = q != 0.0 ? x - 0.5 * p / q : lo - 1.0;
    const bool parabolic = u > lo && u < hi;
    if (parabolic && std::abs(u - x) < kTolerance) break;
    if (!parabolic) u = x - lo > hi - x ? x - 0.381966 * (x - lo) : x + 0.381966 * (hi - x);
    const double fu = f(u);
    if (fu < fx) {
      (u < x ? hi : lo) = x, (u < x ? fhi : flo) = fx;
      x = u, fx = fu;
    } else {
      (u < x ? lo : hi) = u, (u < x ? flo : fhi) = fu;
    }
  }
  return x;
}

// the signed distance of the circle's point at `angle` to the collider
double distance_at(const Collider& collider, const CircleFrame& circle, double angle) {
  Vec3 normal;
  return collider_distance(collider, circle.at(std::cos(angle), std::sin(angle)), normal);
}

// boxes and cylinders from scratch: 16 samples, then the bracket of the best one's neighbours
CirclePointContact searched(const Collider& collider, const CircleFrame& circle) {
  constexpr int kSamples = 16;
  const double step = 2.0 * std::numbers::pi / kSamples;
  const auto f = [&](double angle) { return distance_at(collider, circle, angle); };
  double value[kSamples];
  int best = 0;
  for (int k = 0; k < kSamples; ++k) {
    value[k] = f(k * step);
    if (value[k] < value[best]) best = k;
  }
  const double x = bracketed_minimum(f, (best - 1) * step, best * step, (best + 1) * step,
                                     value[(best + kSamples - 1) % kSamples], value[best],
                                     value[(best + 1) % kSamples]);
  return at_angle(collider, circle, std::cos(x), std::sin(x));
}

// a convex collider's distance is never below the distance to one of its supporting planes, and
// equals it where that plane's face is the nearest feature: when the circle's lowest point
// towards the tightest such plane lies there, it is the deepest point, in closed form (a ring
// lying on a table or a box face). Boxes: the six faces; cylinders: the two caps and the side's
// tangent plane facing the circle's centre.
// the tightest supporting-plane bound of a box or cylinder and the circle's lowest angle towards
// that plane
double face_bound(const Collider& collider, const CircleFrame& circle, double& c, double& s) {
  Vec3 normals[6];
  double offsets[6];  // plane: normal . x = offset
  int faces = 0;
  const Vec3 local = circle.centre - collider.center;
  if (collider.type == Collider::Type::box) {
    for (int axis = 0; axis < 3; ++axis) {
      for (const double side : {-1.0, 1.0}) {
        normals[faces] = side * Vec3::Unit(axis);
        offsets[faces++] = collider.half_extents[axis];
      }
    }
  } else {
    normals[faces] = Vec3::UnitY(), offsets[faces++] = collider.half_height;
    normals[faces] = -Vec3::UnitY(), offsets[faces++] = collider.half_height;
    const Vec3 radial(local.x(), 0.0, local.z());
    if (radial.squaredNorm() > 0.0)
      normals[faces] = radial.normalized(), offsets[faces++] = collider.radius;
  }
  double bound = -1e300;
  for (int k = 0; k < faces; ++k) {
    double ck, sk;
    lowest_angle(circle, normals[k], ck, sk);
    const double lowest = normals[k].dot(local + circle.radius * (ck * circle.x + sk * circle.z));
    if (lowest - offsets[k] > bound) bound = lowest - offsets[k], c = ck, s = sk;
  }
  return bound;
}

bool deepest_on_a_face(const Collider& collider, const CircleFrame& circle,
                       CirclePointContact& out) {
  double c = 1.0, s = 0.0;
  const double bound = face_bound(collider, circle, c, s);
  out = at_angle(collider, circle, c, s);
  return out.distance <= bound + 1e-12 * (circle.radius + std::abs(bound));
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
    case Collider::Type::cylinder: {
      CirclePointContact on_face;
      if (deepest_on_a_face(collider, circle, on_face)) return on_face;
      return searched(collider, circle);
    }
  }
  return at_angle(collider, circle, c, s);
}

CirclePointContact deepest_circle_point_near(const Collider& collider, const CircleFrame& circle,
                                             double cos_s, double sin_s) {
  if (collider.type == Collider::Type::plane || collider.type == Collider::Type::sphere)
    return deepest_circle_point(collider, circle);
  CirclePointContact on_face;
  if (deepest_on_a_face(collider, circle, on_face)) return on_face;
  // a bracket of a third of a radian either side of the last deepest angle
  constexpr double kHalfWidth = 0.35;
  const double start = std::atan2(sin_s, cos_s);
  const auto f = [&](double angle) { return distance_at(collider, circle, angle); };
  const double flo = f(start - kHalfWidth), fx = f(start), fhi = f(start + kHalfWidth);
  // the minimum left the bracket: search from scratch
  if (flo < fx || fhi < fx) return searched(collider, circle);
  const double x =
      bracketed_minimum(f, start - kHalfWidth, start, start + kHalfWidth, flo, fx, fhi);
  return at_angle(collider, circle, std::cos(x), std::sin(x));
}

double circle_collider_lower_bound(const Collider& collider, const CircleFrame& circle) {
  switch (collider.type) {
    case Collider::Type::plane:
    case Collider::Type::sphere:
      return deepest_circle_point(collider, circle).distance;
    case Collider::Type::box:
    case Collider::Type::cylinder: {
      double c, s;
      return face_bound(collider, circle, c, s);
    }
  }
  return -1e300;
}

double circle_collider_bound(const Collider& collider, const Vec3& centre, double radius) {
  // the distance to a surface changes by at most the distance moved
  Vec3 normal;
  return collider_distance(collider, centre, normal) - radius;
}

}  // namespace chainmail

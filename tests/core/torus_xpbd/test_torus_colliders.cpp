// The deepest point of a ring's centre circle in a collider (core/torus_xpbd/torus_colliders.hpp)
// against dense sampling of the circle, for every collider type.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "core/colliders.hpp"
#include "core/torus_xpbd/torus_colliders.hpp"

namespace chainmail {
namespace {

Collider make(Collider::Type type) {
  Collider c;
  c.type = type;
  c.center = Vec3(0.0, 0.0, 0.0);
  c.normal = Vec3(0.2, 1.0, -0.1).normalized();
  c.radius = 0.03;
  c.half_extents = Vec3(0.03, 0.02, 0.04);
  c.half_height = 0.02;
  return c;
}

constexpr int kDense = 20000;

// the lowest signed distance of the circle to the collider over kDense samples: an upper bound of
// the true minimum, within r pi / kDense of it (inside a box or cylinder the distance has kinks,
// where the sampling error is first order)
double sampled_minimum(const Collider& collider, const CircleFrame& circle) {
  double best = 1e300;
  for (int k = 0; k < kDense; ++k) {
    const double s = 2.0 * std::numbers::pi * k / kDense;
    Vec3 normal;
    best = std::min(best, collider_distance(collider, circle.at(std::cos(s), std::sin(s)), normal));
  }
  return best;
}

TEST(TorusColliders, DeepestPointMatchesDenseSamplingOnEveryType) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(-0.045, 0.045);
  for (const auto type : {Collider::Type::plane, Collider::Type::sphere, Collider::Type::box,
                          Collider::Type::cylinder}) {
    const Collider collider = make(type);
    for (int k = 0; k < 60; ++k) {
      const Quat q = Quat(g(rng), g(rng), g(rng), g(rng)).normalized();
      const CircleFrame circle = ring_frame(Vec3(u(rng), u(rng), u(rng)), q, 0.0048);
      const CirclePointContact deepest = deepest_circle_point(collider, circle);
      const double sampled = sampled_minimum(collider, circle);
      SCOPED_TRACE(std::string(to_string(type)) + " case " + std::to_string(k));
      // never above the samples' best, and below it by no more than their spacing can hide
      EXPECT_LE(deepest.distance, sampled + 1e-12);
      EXPECT_GE(deepest.distance, sampled - circle.radius * std::numbers::pi / kDense);
      Vec3 normal;
      EXPECT_NEAR(collider_distance(collider, deepest.point, normal), deepest.distance, 1e-15);
      EXPECT_NEAR((deepest.point - circle.centre).norm(), circle.radius, 1e-12);
    }
  }
}

TEST(TorusColliders, AFlatRingOnAPlaneOrCentredOnASphereTakesAngleZero) {
  const CircleFrame flat = ring_frame(Vec3(0.0, 0.01, 0.0), Quat::Identity(), 0.0048);
  Collider plane;
  plane.type = Collider::Type::plane;
  const CirclePointContact on_plane = deepest_circle_point(plane, flat);
  EXPECT_EQ(on_plane.cos_s, 1.0);
  EXPECT_NEAR(on_plane.distance, 0.01, 1e-15);
  Collider sphere;
  sphere.type = Collider::Type::sphere;
  sphere.radius = 0.005;
  const CirclePointContact on_sphere = deepest_circle_point(sphere, flat);
  EXPECT_EQ(on_sphere.cos_s, 1.0);
  EXPECT_NEAR(on_sphere.distance, std::hypot(0.01, 0.0048) - 0.005, 1e-15);
}

}  // namespace
}  // namespace chainmail

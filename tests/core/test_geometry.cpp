#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/geometry.hpp"
#include "core/ring.hpp"

namespace chainmail {
namespace {

Circle circle(Vec3 centre, Vec3 normal, double radius) {
  return Circle{centre, normal.normalized(), radius};
}

// brute force: dense sampling of both circles
double brute_distance(const Circle& a, const Circle& b, int samples = 3000) {
  auto points = [&](const Circle& c) {
    Vec3 t0 = c.normal.unitOrthogonal(), t1 = c.normal.cross(t0);
    std::vector<Vec3> p(samples);
    for (int k = 0; k < samples; ++k) {
      const double s = 2.0 * std::numbers::pi * k / samples;
      p[k] = c.centre + c.radius * (std::cos(s) * t0 + std::sin(s) * t1);
    }
    return p;
  };
  double best = 1e300;
  for (const Vec3& q : points(b)) best = std::min(best, point_circle_distance(q, a));
  return best;
}

TEST(PointCircleDistance, HandCases) {
  const Circle c = circle(Vec3::Zero(), Vec3::UnitY(), 2.0);
  EXPECT_NEAR(point_circle_distance(Vec3::Zero(), c), 2.0, 1e-15);              // centre
  EXPECT_NEAR(point_circle_distance(Vec3(0, 1, 0), c), std::sqrt(5.0), 1e-15);  // on the axis
  EXPECT_NEAR(point_circle_distance(Vec3(3, 0, 0), c), 1.0, 1e-15);             // in plane, outside
  EXPECT_NEAR(point_circle_distance(Vec3(2, 0.5, 0), c), 0.5, 1e-15);           // above the wire
}

TEST(CircleCircleDistance, CoplanarDisjointIsGap) {
  const Circle a = circle(Vec3::Zero(), Vec3::UnitY(), 1.0);
  const Circle b = circle(Vec3(3.5, 0, 0), Vec3::UnitY(), 1.0);
  EXPECT_NEAR(circle_circle_distance(a, b), 1.5, 1e-12);
}

TEST(CircleCircleDistance, CoplanarIntersectingIsZero) {
  const Circle a = circle(Vec3::Zero(), Vec3::UnitY(), 1.0);
  const Circle b = circle(Vec3(1.0, 0, 0), Vec3::UnitY(), 1.0);
  EXPECT_NEAR(circle_circle_distance(a, b), 0.0, 1e-9);
}

TEST(CircleCircleDistance, PerpendicularLinkedHandCase) {
  // chain links: b in the x/y plane centred at (d, 0, 0): min distance |2c - d| for c < d < 2c
  const double c = 1.0, d = 1.6;
  const Circle a = circle(Vec3::Zero(), Vec3::UnitY(), c);
  const Circle b = circle(Vec3(d, 0, 0), Vec3::UnitZ(), c);
  EXPECT_NEAR(circle_circle_distance(a, b), 2.0 * c - d, 1e-9 * c);
}

TEST(CircleCircleDistance, MatchesBruteForceOnRandomPairs) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Circle a = circle(Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), 1.0);
    const Circle b = circle(Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), 1.0);
    const double fast = circle_circle_distance(a, b);
    const int samples = 20000;
    const double brute = brute_distance(a, b, samples);
    // the refined minimum is never above the dense one, and the dense one is above the true
    // minimum by at most the distance function's Lipschitz bound times half a sample step
    EXPECT_LE(fast, brute + 1e-12);
    EXPECT_LE(brute - fast, std::numbers::pi / samples);
  }
}

TEST(CircleCircleDistance, RefinedToNineDigits) {
  // a case with a known closed form: parallel coaxial circles at height h, radii equal: distance h
  const Circle a = circle(Vec3::Zero(), Vec3::UnitY(), 1.0);
  const Circle b = circle(Vec3(0.3, 0.2, 0), Vec3::UnitY(), 1.0);
  // coplanar-offset parallel circles intersect in projection: distance is the height 0.2
  EXPECT_NEAR(circle_circle_distance(a, b), 0.2, 1e-9 * 0.2);
  // perpendicular case, off-centre, relative accuracy
  const Circle c = circle(Vec3(1.3, 0.0, 0.0), Vec3(0.0, 0.3, 1.0), 1.0);
  const double d = circle_circle_distance(a, c);
  const double dense = circle_circle_distance(a, c, 4096);
  EXPECT_NEAR(d, dense, 1e-9 * dense);
}

TEST(Interpenetration, TouchingIsNotPenetrating) {
  const double a = 0.1;
  const Circle p = circle(Vec3::Zero(), Vec3::UnitY(), 1.0);
  const Circle q = circle(Vec3(2.0 + 2 * a, 0, 0), Vec3::UnitY(), 1.0);  // wires touch
  EXPECT_FALSE(tori_interpenetrate(p, q, a, 1e-3 * a));
  const Circle r = circle(Vec3(2.0 + 1.5 * a, 0, 0), Vec3::UnitY(), 1.0);
  EXPECT_TRUE(tori_interpenetrate(p, r, a, 1e-3 * a));
}

TEST(Linking, HandCases) {
  const Circle a = circle(Vec3::Zero(), Vec3::UnitY(), 1.0);
  // perpendicular through the hole: linked
  EXPECT_TRUE(circles_linked(a, circle(Vec3(1.0, 0, 0), Vec3::UnitZ(), 1.0)));
  // perpendicular but beside the ring: not linked
  EXPECT_FALSE(circles_linked(a, circle(Vec3(2.5, 0, 0), Vec3::UnitZ(), 1.0)));
  // coplanar, overlapping: crosses nothing (no sign change of height)
  EXPECT_FALSE(circles_linked(a, circle(Vec3(1.0, 0, 0), Vec3::UnitY(), 1.0)));
  // parallel stacked: not linked
  EXPECT_FALSE(circles_linked(a, circle(Vec3(0, 0.5, 0), Vec3::UnitY(), 1.0)));
  // a small circle through the hole twice (passes fully through the disk plane inside): 2 crossings
  EXPECT_EQ(disk_crossings(a, circle(Vec3(0, 0, 0), Vec3::UnitZ(), 0.5)), 2);
  // linking is symmetric on a tilted case
  const Circle t = circle(Vec3(0.9, 0.1, 0.05), Vec3(0.1, 0.2, 1.0), 1.0);
  EXPECT_EQ(circles_linked(a, t), circles_linked(t, a));
  EXPECT_TRUE(circles_linked(a, t));
}

}  // namespace
}  // namespace chainmail

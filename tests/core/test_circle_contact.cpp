// Closest points of two circles (core/circle_contact.hpp) against core's sampled circle distance
// (geometry.hpp, golden-section refined), dense brute force and closed forms: linked, unlinked,
// coplanar, coaxial and touching pairs, warm starts and the two minima of a compressed link.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <vector>

#include "core/circle_contact.hpp"
#include "core/geometry.hpp"

namespace chainmail {
namespace {

constexpr double kPi = std::numbers::pi;

Circle as_circle(const CircleFrame& f) {
  return Circle{f.centre, f.normal, f.radius};
}

// dense brute force: the second circle sampled, the closed-form distance of each sample to the
// first circle; an upper bound of the true minimum within r2 (pi / samples)^2 / 2
double brute_distance(const CircleFrame& a, const CircleFrame& b, int samples = 4000) {
  double best = 1e300;
  for (int k = 0; k < samples; ++k) {
    const double t = 2.0 * kPi * k / samples;
    best = std::min(best, point_circle_distance(b.at(std::cos(t), std::sin(t)), as_circle(a)));
  }
  return best;
}

CircleFrame random_circle(std::mt19937& rng, double reach, double radius) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(-reach, reach);
  const Quat q = Quat(g(rng), g(rng), g(rng), g(rng)).normalized();
  return ring_frame(Vec3(u(rng), u(rng), u(rng)), q, radius);
}

// the closest points are on their circles, `distance` is theirs, and the segment between them is
// perpendicular to both circles' tangents (the first-order condition of a minimum)
void expect_stationary(const CircleFrame& a, const CircleFrame& b, const ClosestPoints& p) {
  const double scale = a.radius + b.radius;
  EXPECT_NEAR(point_circle_distance(p.first, as_circle(a)), 0.0, 1e-12 * scale);
  EXPECT_NEAR(point_circle_distance(p.second, as_circle(b)), 0.0, 1e-12 * scale);
  EXPECT_NEAR((p.second - p.first).norm(), p.distance, 1e-15 * scale);
  if (p.distance < 1e-6 * scale) return;
  const Vec3 d = (p.second - p.first) / p.distance;
  const Vec3 ta = a.normal.cross(p.first - a.centre).normalized();
  const Vec3 tb = b.normal.cross(p.second - b.centre).normalized();
  EXPECT_NEAR(d.dot(ta), 0.0, 1e-9);
  EXPECT_NEAR(d.dot(tb), 0.0, 1e-9);
}

// the global minimum agrees with geometry.hpp's sampled-and-refined distance to 1e-9 of the
// distance (1e-9 of the radii where the circles nearly meet) and is never above brute force
void expect_matches_sampled(const CircleFrame& a, const CircleFrame& b) {
  const ClosestPoints p = closest_points(a, b);
  const double sampled = circle_circle_distance(as_circle(a), as_circle(b));
  const double scale = a.radius + b.radius;
  EXPECT_NEAR(p.distance, sampled, 1e-9 * std::max(sampled, 1e-2 * scale));
  EXPECT_LE(p.distance, brute_distance(a, b) + 1e-15 * scale);
  expect_stationary(a, b, p);
}

TEST(CircleContact, RandomPairsMatchTheSampledDistanceAndBruteForce) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> radius(0.3, 1.5);
  int linked = 0, pairs = 120;
  for (int k = 0; k < pairs; ++k) {
    const CircleFrame a = random_circle(rng, 0.6, radius(rng));
    const CircleFrame b = random_circle(rng, 0.6, radius(rng));
    linked += circles_linked(as_circle(a), as_circle(b));
    expect_matches_sampled(a, b);
  }
  // both kinds are exercised
  EXPECT_GT(linked, pairs / 10);
  EXPECT_LT(linked, pairs * 9 / 10);
}

TEST(CircleContact, LinkedRingsMatchTheSampledDistance) {
  // ring pairs as in a chain: b's centre along a's x at 0.2..1.0 of the inner diameter, both
  // tilted and twisted at random; only the linked ones count
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> along(0.1, 0.95), angle(-1.2, 1.2);
  const double c = 4.8, a_wire = 0.8, id = 2.0 * (c - a_wire);
  int checked = 0;
  for (int k = 0; k < 400 && checked < 100; ++k) {
    const CircleFrame a = ring_frame(Vec3::Zero(), Quat::Identity(), c);
    const Quat q = Eigen::AngleAxisd(0.5 * kPi + angle(rng), Vec3::UnitX()) *
                   Eigen::AngleAxisd(angle(rng), Vec3::UnitY()) *
                   Eigen::AngleAxisd(angle(rng), Vec3::UnitZ());
    const CircleFrame b = ring_frame(Vec3(along(rng) * id, 0.3 * angle(rng), 0.0), q, c);
    if (!circles_linked(as_circle(a), as_circle(b))) continue;
    expect_matches_sampled(a, b);
    ++checked;
  }
  EXPECT_EQ(checked, 100);
}

TEST(CircleContact, CoplanarPairs) {
  // disjoint: the gap between the rims; intersecting: zero; concentric: the radii's difference
  const CircleFrame a = circle_frame(Vec3::Zero(), Vec3::UnitY(), 1.0);
  EXPECT_NEAR(closest_points(a, circle_frame(Vec3(3.5, 0, 0), Vec3::UnitY(), 1.0)).distance, 1.5,
              1e-14);
  const ClosestPoints cut = closest_points(a, circle_frame(Vec3(1.2, 0, 0.3), Vec3::UnitY(), 0.9));
  EXPECT_NEAR(cut.distance, 0.0, 1e-12);
  const CircleFrame inner = circle_frame(Vec3::Zero(), -Vec3::UnitY(), 0.6);
  EXPECT_NEAR(closest_points(a, inner).distance, 0.4, 1e-14);
  EXPECT_NEAR(closest_points(inner, a).distance, 0.4, 1e-14);
  // inside and off-centre: the gap on the side where the rims come nearest
  const CircleFrame off = circle_frame(Vec3(0.2, 0, 0), Vec3::UnitY(), 0.6);
  const ClosestPoints p = closest_points(a, off);
  EXPECT_NEAR(p.distance, 0.2, 1e-14);
  EXPECT_NEAR(p.second.x(), 0.8, 1e-9);
  expect_matches_sampled(a, circle_frame(Vec3(1.7, 0, -0.4), Vec3::UnitY(), 0.5));
}

TEST(CircleContact, CoaxialPairsKeepTheirWarmStart) {
  // parallel circles on one axis: every angle is a minimum, sqrt(h^2 + (r1 - r2)^2) apart
  const CircleFrame a = circle_frame(Vec3::Zero(), Vec3::UnitY(), 1.0);
  const CircleFrame b = ring_frame(Vec3(0, 0.3, 0), Quat::Identity(), 0.7);
  const double expected = std::hypot(0.3, 0.3);
  for (const double t : {0.0, 1.0, 2.5, -2.0}) {
    const ClosestPoints p = refine_closest_points(a, b, std::cos(t), std::sin(t));
    EXPECT_NEAR(p.distance, expected, 1e-14) << t;
    EXPECT_NEAR(std::atan2(p.sin_t, p.cos_t), t, 1e-12) << "the start angle is kept";
    expect_stationary(a, b, p);
  }
  EXPECT_NEAR(closest_points(a, b).distance, expected, 1e-14);
  // the same radius, stacked: the axis distance
  const CircleFrame stacked = ring_frame(Vec3(0, -0.25, 0), Quat::Identity(), 1.0);
  EXPECT_NEAR(closest_points(a, stacked).distance, 0.25, 1e-14);
  // perpendicular through the centre: the second circle crosses the first one's axis, where
  // every point of the first is equally near; the minima are where it meets the first's plane
  const CircleFrame across = circle_frame(Vec3::Zero(), Vec3::UnitZ(), 0.5);
  EXPECT_NEAR(closest_points(a, across).distance, 0.5, 1e-14);
}

TEST(CircleContact, TouchingChainLinksAreTwoWireRadiiApart) {
  // perpendicular links pulled straight: the wires touch where they hook, at 2c - d
  const double c = 4.8, a_wire = 0.8;
  const CircleFrame a = ring_frame(Vec3::Zero(), Quat::Identity(), c);
  const Quat quarter(Eigen::AngleAxisd(0.5 * kPi, Vec3::UnitX()));
  for (const double d : {2.0 * (c - a_wire), 6.0, 8.5}) {
    const CircleFrame b = ring_frame(Vec3(d, 0, 0), quarter, c);
    const ClosestPoints p = closest_points(a, b);
    EXPECT_NEAR(p.distance, 2.0 * c - d, 1e-12 * c) << d;
    EXPECT_NEAR((p.first - Vec3(c, 0, 0)).norm(), 0.0, 1e-9 * c) << d;
    expect_matches_sampled(a, b);
  }
}

TEST(CircleContact, CompressedLinkHasTwoMinima) {
  // perpendicular links with centres d apart, d < 2a: the wires meet on both sides, d apart each
  const double c = 4.8, d = 1.0;
  const CircleFrame a = ring_frame(Vec3::Zero(), Quat::Identity(), c);
  const CircleFrame b =
      ring_frame(Vec3(d, 0, 0), Quat(Eigen::AngleAxisd(0.5 * kPi, Vec3::UnitX())), c);
  ClosestPoints minima[4];
  const int count = local_closest_points(a, b, minima, 4);
  ASSERT_EQ(count, 2);
  EXPECT_NEAR(minima[0].distance, d, 1e-12 * c);
  EXPECT_NEAR(minima[1].distance, d, 1e-12 * c);
  EXPECT_NEAR(std::abs(minima[0].first.x() - minima[1].first.x()), 2.0 * c, 1e-9 * c);
}

TEST(CircleContact, TwinMinimaASampleApartFindTheDeeperOne) {
  // two linked rings of a taut 4-in-1 sheet (hung for 0.2 s): the wire meets the other ring at two
  // minima within one sample step of 32, the shallower one the only sampled local minimum; the
  // global minimum and the torus depth test must find the deeper one
  const Circle a{Vec3(0.19515282720189817, 0.15027425026459681, 0),
                 Vec3(0.44242388084897066, -0.014039146144667832, -0.8966961648351488),
                 0.0048000000000000004};
  const Circle b{Vec3(0.19185410559325378, 0.14318793082223413, 0),
                 Vec3(-0.44242701101351756, 0.013940154073047713, -0.89669616483514891),
                 0.0048000000000000004};
  const CircleFrame fa = circle_frame(a.centre, a.normal, a.radius);
  const CircleFrame fb = circle_frame(b.centre, b.normal, b.radius);
  ClosestPoints minima[4];
  ASSERT_GE(local_closest_points(fa, fb, minima, 4, 32), 2);
  EXPECT_LT(minima[0].distance, minima[1].distance - 1e-7);  // apart by 2e-7 m, both found
  const double reference = circle_circle_distance(a, b, 4096);
  EXPECT_NEAR(closest_points(fa, fb).distance, reference, 1e-12 * reference);
  // a wire radius of 0.8 mm (2a = 1.6 mm) with the metrics' tolerance: interpenetrating
  const double wire = 0.0008, tolerance = 1e-3 * wire;
  ASSERT_LT(reference, 2.0 * wire - tolerance);
  EXPECT_TRUE(tori_interpenetrate(a, b, wire, tolerance));
  const std::optional<double> below = circles_closer_than(a, b, 2.0 * wire - tolerance);
  ASSERT_TRUE(below.has_value());
  EXPECT_NEAR(*below, reference, 1e-12 * reference);
}

TEST(CircleContact, WarmStartFollowsAMovingPairInAFewSteps) {
  // a linked pair moved a little per step, solved from the previous angle with three Newton
  // steps, stays on the exact global minimum
  const double c = 4.8;
  const CircleFrame a = ring_frame(Vec3::Zero(), Quat::Identity(), c);
  ClosestPoints last = closest_points(
      a, ring_frame(Vec3(7.0, 0, 0), Quat(Eigen::AngleAxisd(1.3, Vec3::UnitX())), c));
  for (int k = 1; k <= 200; ++k) {
    const double s = 0.01 * k;
    const Quat q = Eigen::AngleAxisd(1.3 + 0.4 * std::sin(s), Vec3::UnitX()) *
                   Eigen::AngleAxisd(0.3 * s, Vec3::UnitY());
    const CircleFrame b = ring_frame(Vec3(7.0 - s, 0.5 * std::sin(2 * s), 0.2 * s), q, c);
    last = refine_closest_points(a, b, last.cos_t, last.sin_t, 3, 1e-12);
    const ClosestPoints fresh = closest_points(a, b);
    ASSERT_NEAR(last.distance, fresh.distance, 1e-9 * c) << "step " << k;
  }
}

TEST(CircleContact, NoNewtonStepGivesThePointsAtTheStartAngleNeverNearerThanTheMinimum) {
  // what a retried contact uses: the angle its first solve found, on a pose moved a little since.
  // The distance there is exact for that angle and an upper bound of the minimum
  std::mt19937 rng(7);
  const double c = 4.8;
  for (int k = 0; k < 200; ++k) {
    const CircleFrame a = random_circle(rng, 3.0, c), b = random_circle(rng, 3.0, c);
    const double t = 2.0 * kPi * k / 200.0;
    const ClosestPoints at = refine_closest_points(a, b, std::cos(t), std::sin(t), 0);
    EXPECT_NEAR(at.cos_t, std::cos(t), 1e-15);
    EXPECT_NEAR((at.second - b.at(std::cos(t), std::sin(t))).norm(), 0.0, 1e-12 * c);
    EXPECT_NEAR(at.distance, point_circle_distance(at.second, as_circle(a)), 1e-12 * c);
    EXPECT_GE(at.distance, closest_points(a, b).distance - 1e-12 * c);
  }
}

}  // namespace
}  // namespace chainmail

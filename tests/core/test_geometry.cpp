#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <vector>

#include "core/geometry.hpp"
#include "core/ring.hpp"
#include "core/weave.hpp"

namespace chainmail {
namespace {

Circle circle(Vec3 centre, Vec3 normal, double radius) {
  return Circle{centre, normal.normalized(), radius};
}

// a rigid motion (rotation, then translation) with a uniformly random rotation
struct Rigid {
  Quat rotation;
  Vec3 translation;
  Circle operator()(const Circle& c) const {
    return Circle{rotation * c.centre + translation, (rotation * c.normal).normalized(), c.radius};
  }
};

Rigid random_rigid(std::mt19937& rng, double reach) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(-reach, reach);
  const Quat q = Quat(g(rng), g(rng), g(rng), g(rng)).normalized();
  return Rigid{q, Vec3(u(rng), u(rng), u(rng))};
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

// independent reference for the distance between two circles: `b` sampled densely in a basis of
// its own, each point's distance to `a` in closed form (height over a's plane, radial offset in
// it), every sampled local minimum refined by golden-section search to 1e-13 rad
double reference_distance(const Circle& a, const Circle& b) {
  const Vec3 u = b.normal.unitOrthogonal(), v = b.normal.cross(u);
  auto f = [&](double s) {
    const Vec3 d = b.centre + b.radius * (std::cos(s) * u + std::sin(s) * v) - a.centre;
    const double height = d.dot(a.normal);
    return std::hypot(height, (d - height * a.normal).norm() - a.radius);
  };
  constexpr int kSamples = 4096;
  const double step = 2.0 * std::numbers::pi / kSamples;
  std::vector<double> value(kSamples);
  for (int k = 0; k < kSamples; ++k) value[k] = f(k * step);
  double best = *std::min_element(value.begin(), value.end());
  const double inv_phi = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int k = 0; k < kSamples; ++k) {
    if (value[k] > value[(k + kSamples - 1) % kSamples] || value[k] > value[(k + 1) % kSamples])
      continue;
    double lo = (k - 1) * step, hi = (k + 1) * step;
    while (hi - lo > 1e-13) {
      const double x1 = hi - inv_phi * (hi - lo), x2 = lo + inv_phi * (hi - lo);
      if (f(x1) < f(x2)) {
        hi = x2;
      } else {
        lo = x1;
      }
    }
    best = std::min(best, f(0.5 * (lo + hi)));
  }
  return best;
}

TEST(CircleCircleDistance, RefinedToNineDigits) {
  // parallel planes 0.2 apart, projections crossing (lateral offset 0.3 < 2r): the circles pass
  // right above each other where the projections cross, so the distance is the height 0.2
  const Circle a = circle(Vec3::Zero(), Vec3::UnitY(), 1.0);
  const Circle b = circle(Vec3(0.3, 0.2, 0), Vec3::UnitY(), 1.0);
  EXPECT_NEAR(circle_circle_distance(a, b), 0.2, 1e-9 * 0.2);
  // tilted, off-centre: c's plane holds the x axis, c meets a's plane at x = 0.3 and 2.3, and the
  // nearest points are (0.3, 0, 0) and (1, 0, 0): distance 0.7. Against the reference, which
  // knows nothing of the closed form, and on random pairs at the default sample count
  const Circle c = circle(Vec3(1.3, 0.0, 0.0), Vec3(0.0, 0.3, 1.0), 1.0);
  const double reference = reference_distance(a, c);
  EXPECT_NEAR(reference, 0.7, 1e-12);
  EXPECT_NEAR(circle_circle_distance(a, c), reference, 1e-9 * reference);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 100; ++trial) {
    const Circle p = circle(Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), 1.0);
    const Circle q = circle(Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), 0.7);
    const double expected = reference_distance(p, q);
    if (expected < 1e-3) continue;  // crossing circles: no relative accuracy to speak of
    EXPECT_NEAR(circle_circle_distance(p, q), expected, 1e-9 * expected) << trial;
  }
}

TEST(Interpenetration, TouchingIsNotPenetrating) {
  const double a = 0.1;
  const Circle p = circle(Vec3::Zero(), Vec3::UnitY(), 1.0);
  const Circle q = circle(Vec3(2.0 + 2 * a, 0, 0), Vec3::UnitY(), 1.0);  // wires touch
  EXPECT_FALSE(tori_interpenetrate(p, q, a, 1e-3 * a));
  const Circle r = circle(Vec3(2.0 + 1.5 * a, 0, 0), Vec3::UnitY(), 1.0);
  EXPECT_TRUE(tori_interpenetrate(p, r, a, 1e-3 * a));
}

TEST(Interpenetration, CloserThanGivesExactDistances) {
  // configurations whose centre-circle distance is known in closed form, at random placements:
  // - parallel planes at height h, projections crossing (lateral offset e < 2c): the circles pass
  //   right above each other where the projections cross, so the distance is h (e = 0: coaxial)
  // - coplanar, centres D > 2c apart: closest points on the line of centres, D - 2c apart
  // - the same centre, any tilt: the circles share the two points on the planes' common line: 0
  const double c = 0.0048, a = 0.0008;
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Rigid move = random_rigid(rng, 1.0);
    const Circle ring = circle(Vec3::Zero(), Vec3::UnitY(), c);
    const double h = 2.0 * a * u(rng), e = 1.9 * c * u(rng), gap = 2.0 * a * u(rng);
    const double tilt = std::numbers::pi * u(rng);
    const struct {
      Circle other;
      double distance;
    } cases[] = {{circle(Vec3(e, h, 0), Vec3::UnitY(), c), h},
                 {circle(Vec3(0, 0, 2 * c + gap), Vec3::UnitY(), c), gap},
                 {circle(Vec3::Zero(), Vec3(0, std::cos(tilt), std::sin(tilt)), c), 0.0}};
    for (const auto& [other, distance] : cases) {
      const std::optional<double> below = circles_closer_than(move(ring), move(other), 2.0 * a);
      ASSERT_TRUE(below.has_value()) << "exact distance " << distance;
      EXPECT_NEAR(*below, distance, 1e-9 * c);
      // above the limit: nothing, and the same answer as the torus test
      EXPECT_FALSE(circles_closer_than(move(ring), move(other), distance - 1e-6 * c));
      EXPECT_FALSE(tori_interpenetrate(move(ring), move(other), a, 2.0 * a - distance + 1e-6 * c));
      EXPECT_TRUE(tori_interpenetrate(move(ring), move(other), a, 2.0 * a - distance - 1e-6 * c));
    }
  }
  // far apart: nothing
  EXPECT_FALSE(circles_closer_than(circle(Vec3::Zero(), Vec3::UnitY(), c),
                                   circle(Vec3(1, 0, 0), Vec3::UnitY(), c), 2.0 * a));
}

TEST(Interpenetration, CloserThanMatchesTheReference) {
  // random ring-sized pairs within reach of each other, the limit on either side of the
  // reference distance: the closed-form path finds the same minimum, or rightly none
  const double c = 0.0048;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int found = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Circle p = circle(c * Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), c);
    const Circle q = circle(c * Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), c);
    const double expected = reference_distance(p, q);
    if (expected < 1e-3 * c) continue;  // crossing circles: no relative accuracy to speak of
    const std::optional<double> below = circles_closer_than(p, q, 1.001 * expected);
    ASSERT_TRUE(below.has_value()) << trial;
    EXPECT_NEAR(*below, expected, 1e-9 * expected) << trial;
    EXPECT_FALSE(circles_closer_than(p, q, 0.999 * expected).has_value()) << trial;
    ++found;
  }
  EXPECT_GT(found, 200);
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

// the degenerate cases below are placed at random rigid positions: round-off then puts tiny
// heights of either sign on what is exactly a plane, and the answer must not depend on them
constexpr int kPlacements = 2000;

TEST(Linking, CoplanarPairsAreNeverLinkedAnywhere) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const double c : {1.0, 0.0048}) {
    int linked = 0, crossings = 0;
    for (int trial = 0; trial < kPlacements; ++trial) {
      // b in a's plane, overlapping it (centre distance below the sum of radii)
      const double rb = c * (0.3 + 1.4 * u(rng)), angle = 2.0 * std::numbers::pi * u(rng);
      const double d = (c + rb) * u(rng);
      const Circle a = circle(Vec3::Zero(), Vec3::UnitY(), c);
      const Circle b = circle(d * Vec3(std::cos(angle), 0.0, std::sin(angle)), Vec3::UnitY(), rb);
      const Rigid move = random_rigid(rng, 1000.0 * c);
      Circle ma = move(a), mb = move(b);
      // and a 1e-15 m jitter on top
      mb.centre += 1e-15 * Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
      linked += circles_linked(ma, mb) + circles_linked(mb, ma);
      crossings += disk_crossings(ma, mb) + disk_crossings(mb, ma);
    }
    EXPECT_EQ(linked, 0) << "c = " << c;
    EXPECT_EQ(crossings, 0) << "c = " << c;
  }
}

TEST(Linking, RimTouchIsOutsideTheOpenDisk) {
  // b perpendicular to a, its plane through a's centre, meeting a's plane at x = d - rb and
  // x = d + rb; one of them exactly on a's rim (x = 1)
  std::mt19937 rng(12);
  const Circle a = circle(Vec3::Zero(), Vec3::UnitY(), 1.0);
  int wrong = 0;
  for (int trial = 0; trial < kPlacements; ++trial) {
    const Rigid move = random_rigid(rng, 100.0);
    // rims touch from outside: crossings at the rim and beyond it: none inside
    const Circle outside = circle(Vec3(1.3, 0, 0), Vec3::UnitZ(), 0.3);
    // rims touch from inside: crossings at the rim and inside: exactly one inside
    const Circle inside = circle(Vec3(0.7, 0, 0), Vec3::UnitZ(), 0.3);
    wrong += disk_crossings(move(a), move(outside)) != 0;
    wrong += disk_crossings(move(a), move(inside)) != 1;
  }
  EXPECT_EQ(wrong, 0);
}

TEST(Linking, TangentTouchIsNoCrossing) {
  // b in the y/z plane, its lowest (or highest) point resting on a's plane, inside the disk, on
  // the rim or outside: it touches without crossing
  std::mt19937 rng(13);
  const Circle a = circle(Vec3::Zero(), Vec3::UnitY(), 1.0);
  int wrong = 0;
  for (int trial = 0; trial < kPlacements; ++trial) {
    const Rigid move = random_rigid(rng, 100.0);
    for (const double x : {0.0, 0.4, 1.0, 1.5}) {
      for (const double side : {1.0, -1.0}) {
        const Circle b = circle(Vec3(x, side * 0.5, 0), Vec3::UnitX(), 0.5);
        wrong += disk_crossings(move(a), move(b)) != 0;
      }
    }
  }
  EXPECT_EQ(wrong, 0);
}

TEST(Linking, NearCoplanarTiltsMatchTheExactConstruction) {
  // b centred at (d, 0, 0) on a's plane, tilted out of it by theta about the x axis: its plane
  // contains the x axis, so it crosses a's plane exactly at x = d - rb and x = d + rb, and it is
  // linked with a iff exactly one of those lies inside a's unit disk (the Hopf link at theta =
  // pi/2)
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Circle a = circle(Vec3::Zero(), Vec3::UnitY(), 1.0);
  int wrong = 0, flat_linked = 0, linked = 0, cases = 0;
  for (int trial = 0; trial < kPlacements; ++trial) {
    const double d = 2.5 * u(rng), rb = 0.2 + 1.3 * u(rng);
    const double near = std::abs(d - rb), far = d + rb;
    if (std::abs(near - 1.0) < 1e-6 || std::abs(far - 1.0) < 1e-6) continue;  // on the rim
    const bool expected = (near < 1.0) != (far < 1.0);
    const Rigid move = random_rigid(rng, 10.0);
    for (const double theta : {0.5, 1e-3, 1e-5, -1e-6, 1e-7}) {
      const Circle b = circle(Vec3(d, 0, 0), Vec3(0, std::cos(theta), std::sin(theta)), rb);
      wrong += circles_linked(move(a), move(b)) != expected;
      wrong += circles_linked(move(b), move(a)) != expected;  // linking is symmetric
      linked += expected, ++cases;
    }
    // tilts far below the band (1e-9 of the radii) are coplanar: never linked
    for (const double theta : {1e-13, -1e-14}) {
      const Circle b = circle(Vec3(d, 0, 0), Vec3(0, std::cos(theta), std::sin(theta)), rb);
      flat_linked += circles_linked(move(a), move(b));
    }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(flat_linked, 0);
  EXPECT_GT(linked, cases / 5);  // both answers are exercised
  EXPECT_LT(linked, cases * 4 / 5);
}

TEST(Linking, MayLinkHoldsForEveryLinkedPair) {
  // ring-sized pairs within reach, at random rigid placements, half of them placed near a linked
  // configuration (through the hole, tilted a little): every linked pair passes the cheap test,
  // and most unlinked ones fail it (what it is for)
  const double c = 0.0048;
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int linked = 0, unlinked = 0, rejected = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Circle p = circle(Vec3::Zero(), Vec3::UnitY(), c), q;
    if (trial % 2 == 0) {
      q = circle(c * Vec3(1.0 + 0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng)),
                 Vec3(0.3 * u(rng), 0.3 * u(rng), 1.0), c);
    } else {
      q = circle(2.0 * c * Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), c);
    }
    const Rigid move = random_rigid(rng, 100.0 * c);
    p = move(p), q = move(q);
    for (const auto& [first, second] : {std::pair{p, q}, std::pair{q, p}}) {
      if (circles_linked(first, second)) {
        ++linked;
        ASSERT_TRUE(circles_may_link(first, second)) << "trial " << trial;
      } else {
        ++unlinked;
        rejected += !circles_may_link(first, second);
      }
    }
  }
  EXPECT_GT(linked, 5000);
  EXPECT_GT(rejected, unlinked / 2);
}

TEST(Linking, WeaveNeighboursStayLinkedAnywhere) {
  const RingGeometry ring;
  WeaveSpec spec;
  spec.rows = spec.cols = 6;
  const Weave weave = make_weave(spec, ring);
  std::mt19937 rng(15);
  int broken = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const Rigid move = random_rigid(rng, 10.0);
    auto ring_at = [&](int i) {
      const Quat q(weave.rest_orientation(0, i), weave.rest_orientation(1, i),
                   weave.rest_orientation(2, i), weave.rest_orientation(3, i));
      return move(ring_circle(weave.rest_position.col(i), q, ring.centre_radius));
    };
    for (const RingPair& link : weave.links) {
      broken += !circles_linked(ring_at(link.a), ring_at(link.b));
      broken += !circles_linked(ring_at(link.b), ring_at(link.a));
    }
  }
  EXPECT_EQ(broken, 0);
}

}  // namespace
}  // namespace chainmail

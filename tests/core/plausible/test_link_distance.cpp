// The largest centre distance of two linked rings (core/plausible/link_distance.hpp): the straight
// chain's hook in closed form, coplanar rings never linked, the maximum a contact, the
// orientation's symmetries and the table's interpolation.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/circle_contact.hpp"
#include "core/geometry.hpp"
#include "core/plausible/link_distance.hpp"

namespace chainmail {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

LinkOrientation degrees(double tilt_first, double tilt_second, double twist) {
  return {tilt_first * kDegree, tilt_second * kDegree, twist * kDegree};
}

TEST(LinkDistance, AStraightChainHooksAtTheInnerDiameter) {
  // both planes through the centre line, a quarter turn apart: the wires hook at 2c - d = 2a
  for (const double aspect : {3.5, 5.0, 8.0}) {
    const RingGeometry ring = RingGeometry::from_diameters(0.0016, aspect * 0.0016, 7850.0);
    EXPECT_NEAR(max_link_distance(degrees(0, 0, 90), ring), ring.inner_diameter(),
                1e-12 * ring.centre_radius)
        << aspect;
  }
}

TEST(LinkDistance, CoplanarAndFacingRingsAreNeverLinked) {
  const RingGeometry ring;
  // twist 0 or 180 with both planes through the line: one plane, no ring through the other
  EXPECT_EQ(max_link_distance(degrees(0, 0, 0), ring), 0.0);
  EXPECT_EQ(max_link_distance(degrees(0, 0, 180), ring), 0.0);
  // a ring facing the other (its axis along the line): the other crosses its plane twice at one
  // distance from its axis, both inside or both outside its hole
  EXPECT_EQ(max_link_distance(degrees(90, 0, 0), ring), 0.0);
}

TEST(LinkDistance, TheMaximumIsWhereTheWiresTouch) {
  const RingGeometry ring;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> tilt(0.0, 35.0), twist(40.0, 140.0);
  int found = 0;
  for (int k = 0; k < 40; ++k) {
    const LinkOrientation o = degrees(tilt(rng), tilt(rng), twist(rng));
    const double d = max_link_distance(o, ring);
    if (d == 0.0) continue;
    ++found;
    Vec3 first, second;
    link_axes(o, first, second);
    const double c = ring.centre_radius;
    const Circle a{Vec3::Zero(), first, c}, b{Vec3(d, 0, 0), second, c};
    EXPECT_TRUE(circles_linked(a, b));
    const double gap =
        closest_points(circle_frame(a.centre, a.normal, c), circle_frame(b.centre, b.normal, c))
            .distance;
    EXPECT_NEAR(gap, 2.0 * ring.wire_radius, 1e-9 * c);
    // never beyond the straight chain's hook
    EXPECT_LE(d, ring.inner_diameter() * (1.0 + 1e-12));
  }
  EXPECT_GT(found, 30);
}

TEST(LinkDistance, OrientationIsSymmetricAndRoundTrips) {
  const RingGeometry ring;
  const LinkOrientation o = degrees(10, 25, 70);
  // the rings swapped: the same distance
  EXPECT_NEAR(max_link_distance(o, ring), max_link_distance(degrees(25, 10, 70), ring),
              1e-12 * ring.centre_radius);
  // axes built from an orientation give it back, whatever their signs, turned about the line
  Vec3 first, second;
  link_axes(o, first, second);
  const Quat turn(Eigen::AngleAxisd(0.7, Vec3::UnitX()));
  const LinkOrientation back = link_orientation(-(turn * first), turn * second, Vec3(3, 0, 0));
  EXPECT_NEAR(back.tilt_first, o.tilt_first, 1e-12);
  EXPECT_NEAR(back.tilt_second, o.tilt_second, 1e-12);
  EXPECT_NEAR(back.twist, o.twist, 1e-12);
  // and seen from the second ring (the line reversed), the tilts swap
  const LinkOrientation reversed = link_orientation(second, first, Vec3(-1, 0, 0));
  EXPECT_NEAR(reversed.tilt_first, o.tilt_second, 1e-12);
  EXPECT_NEAR(reversed.tilt_second, o.tilt_first, 1e-12);
  EXPECT_NEAR(reversed.twist, o.twist, 1e-12);
}

TEST(LinkDistance, TableIsExactAtItsNodesAndCloseBetween) {
  const RingGeometry ring;
  const LinkDistanceTable table(ring, 7, 13);
  for (int i = 0; i < table.tilt_nodes(); i += 2) {
    for (int k = 0; k < table.twist_nodes(); k += 3) {
      const LinkOrientation o = table.node(i, 1, k);
      EXPECT_NEAR(table.max_distance(o), max_link_distance(o, ring), 1e-12 * ring.centre_radius);
    }
  }
  // between nodes in the smooth middle of the chain's plateau: within a few percent
  const LinkOrientation middle = degrees(5, 10, 80);
  EXPECT_NEAR(table.max_distance(middle), max_link_distance(middle, ring),
              0.03 * ring.inner_diameter());
  // from axes and a centre line, as a model holds them
  Vec3 first, second;
  link_axes(middle, first, second);
  EXPECT_DOUBLE_EQ(table.max_distance(first, second, Vec3(0.01, 0, 0)), table.max_distance(middle));
}

}  // namespace
}  // namespace chainmail

// The stateless position constraints: corrections that meet the bound exactly, shared by inverse
// mass, and the violation they report (the sweeps' residual) equal to the distance corrected.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/plausible/constraints.hpp"

namespace chainmail {
namespace {

TEST(EdgeConstraint, StretchedEdgeMeetsItsMaximumAndReportsTheExcess) {
  const Vec3 p0(0.0, 0.0, 0.0), p1(0.3, 0.4, 0.0);  // length 0.5
  Vec3 corr0 = Vec3::Zero(), corr1 = Vec3::Zero();
  const double violation = solve_edge_constraint(p0, 1.0, p1, 3.0, 0.1, 0.4, corr0, corr1);
  EXPECT_NEAR(violation, 0.1, 1e-15);
  EXPECT_NEAR(((p1 + corr1) - (p0 + corr0)).norm(), 0.4, 1e-15);
  // the lighter end (w = 3) moves three times as far, along the edge
  EXPECT_NEAR(corr1.norm(), 3.0 * corr0.norm(), 1e-15);
  EXPECT_NEAR((corr1 - corr0).norm(), violation, 1e-15);
}

TEST(EdgeConstraint, CompressedEdgeMeetsItsMinimum) {
  const Vec3 p0(0.0, 0.0, 0.0), p1(0.0, 0.0, 0.05);
  Vec3 corr0 = Vec3::Zero(), corr1 = Vec3::Zero();
  const double violation = solve_edge_constraint(p0, 0.0, p1, 1.0, 0.1, 0.4, corr0, corr1);
  EXPECT_NEAR(violation, 0.05, 1e-15);
  EXPECT_EQ(corr0, Vec3::Zero());  // pinned
  EXPECT_NEAR((p1 + corr1 - p0).norm(), 0.1, 1e-15);
}

TEST(EdgeConstraint, WithinBoundsOrImmovableIsUntouched) {
  Vec3 corr0(7, 7, 7), corr1(7, 7, 7);
  EXPECT_EQ(solve_edge_constraint(Vec3::Zero(), 1.0, Vec3(0.2, 0, 0), 1.0, 0.1, 0.4, corr0, corr1),
            0.0);
  EXPECT_EQ(solve_edge_constraint(Vec3::Zero(), 0.0, Vec3(0.9, 0, 0), 0.0, 0.1, 0.4, corr0, corr1),
            0.0);
  EXPECT_EQ(corr0, Vec3(7, 7, 7));
  EXPECT_EQ(corr1, Vec3(7, 7, 7));
}

TEST(AttachmentConstraint, PullsBackToTheSphereAroundThePin) {
  const Vec3 pin(1.0, 2.0, 3.0), p = pin + Vec3(0.0, -0.6, 0.8);  // 1.0 from the pin
  Vec3 corr = Vec3::Zero();
  EXPECT_NEAR(solve_attachment_constraint(p, pin, 0.75, corr), 0.25, 1e-15);
  EXPECT_NEAR((p + corr - pin).norm(), 0.75, 1e-15);
  EXPECT_NEAR(corr.norm(), 0.25, 1e-15);
  EXPECT_EQ(solve_attachment_constraint(p, pin, 1.5, corr), 0.0);  // inside: free
}

TEST(SlideTowardFaces, TurnsTheNormalTowardTheAxesOnTheirSide) {
  const Vec3 normal = Vec3::UnitX();
  // no axes: straight along the normal
  EXPECT_TRUE(slide_toward_faces(normal, Vec3::Zero(), Vec3::Zero(), 0.1).isApprox(normal));
  // coins leaning the same way (axes mostly along the line, tipped toward +z): the push turns
  // toward +z, whichever sign each axis has
  const Vec3 lean = Vec3(1.0, 0.0, 0.5).normalized();
  const Vec3 way = slide_toward_faces(normal, lean, -lean, 0.1);
  EXPECT_NEAR(way.norm(), 1.0, 1e-15);
  EXPECT_GT(way.z(), 0.0);
  EXPECT_NEAR(way.y(), 0.0, 1e-15);
  // each axis adds slip times its part across the normal: 2 * 0.1 * 0.5 / |lean| along z
  const double across = 2.0 * 0.1 * lean.z();
  EXPECT_NEAR(way.z() / way.x(), across, 1e-14);
  // the other lean turns it the other way
  EXPECT_LT(slide_toward_faces(normal, Vec3(1.0, 0.0, -0.5).normalized(), lean, 0.0).z(), 1e-15);
  EXPECT_LT(slide_toward_faces(normal, Vec3(1.0, 0.0, -0.5).normalized(),
                               Vec3(1.0, 0.0, -0.5).normalized(), 0.1)
                .z(),
            0.0);
  // the push keeps closing a gap along the normal: dot >= 1 / sqrt(1 + 4 slip^2)
  const Vec3 across_only = slide_toward_faces(normal, Vec3::UnitZ(), Vec3::UnitZ(), 1.0);
  EXPECT_NEAR(across_only.dot(normal), 1.0 / std::sqrt(5.0), 1e-15);
}

TEST(ClearAlong, HoldsOnlyWhereTheNormalisedTestHolds) {
  // random separations and directions of every scale the contact sweep meets, many within a
  // rounding of the range: wherever the cheap test says clear, the normalised one agrees; and it
  // says clear for most pairs well past the range (it would be no use otherwise)
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), scale(-9.0, -1.0);
  const double range = 0.0064;  // m
  int clear = 0, far = 0, near = 0;
  for (int k = 0; k < 200000; ++k) {
    const Vec3 way = std::pow(10.0, scale(random)) * Vec3(unit(random), unit(random), unit(random));
    const Vec3 n = way / way.norm();
    // half of them a few roundings from the range along the way, half anywhere near it
    const double along = k % 2 ? range * (1.0 + 1e-15 * std::round(20.0 * unit(random)))
                               : range * (1.0 + unit(random));
    const Vec3 apart = along * n + range * Vec3(unit(random), unit(random), unit(random)).cross(n);
    const double gap = apart.dot(n) - range;  // the sweep's test: clear where gap >= 0
    if (clear_along(apart, way, range)) {
      ++clear;
      EXPECT_GE(gap, 0.0) << k;
    }
    if (gap > 1e-6 * range) {
      ++far;
      near += !clear_along(apart, way, range);
    }
  }
  EXPECT_GT(clear, 0);
  EXPECT_LT(near, far / 1000);  // well past the margin, nearly every clear pair is found clear
}

}  // namespace
}  // namespace chainmail

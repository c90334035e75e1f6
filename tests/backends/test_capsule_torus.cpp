// The capsule torus, the rigid backends' ring shape: its surface and inner-diameter errors
// against sampled geometry.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "backends/capsule_torus.hpp"
#include "core/ring.hpp"

namespace chainmail {
namespace {

TEST(CapsuleTorus, ErrorsMatchTheSampledPolygon) {
  // default ring: WD 1.6 mm, ID 8 mm (c / a = 6)
  const RingGeometry ring = RingGeometry::from_diameters(0.0016, 0.008, 7850.0);
  const double a = ring.wire_radius, c = ring.centre_radius;
  const int pieces = 28;  // the rigid backends' default

  for (int n : {pieces, 7, 12}) {
    const CapsuleTorus fit = capsule_torus(a, c, n);
    // sample the polygon's sides: distance to the centre circle, and its radial extent per angle
    double deviation = 0.0;
    constexpr int kAngles = 3600;
    std::vector<double> radius(kAngles, 0.0);  // polygon radius by direction (binned), m
    for (int piece = 0; piece < n; ++piece) {
      const double s0 = 2.0 * std::numbers::pi * piece / n;
      const double s1 = 2.0 * std::numbers::pi * (piece + 1) / n;
      const Eigen::Vector2d v0 = fit.vertex_radius * Eigen::Vector2d(std::cos(s0), std::sin(s0));
      const Eigen::Vector2d v1 = fit.vertex_radius * Eigen::Vector2d(std::cos(s1), std::sin(s1));
      EXPECT_NEAR((v1 - v0).norm(), fit.capsule_length, 1e-12);
      for (int k = 0; k <= 2000; ++k) {
        const Eigen::Vector2d p = v0 + (v1 - v0) * (k / 2000.0);
        deviation = std::max(deviation, std::abs(p.norm() - c));
        double angle = std::atan2(p.y(), p.x());
        if (angle < 0) angle += 2.0 * std::numbers::pi;
        const int bin =
            std::min(kAngles - 1, static_cast<int>(angle / (2.0 * std::numbers::pi) * kAngles));
        radius[bin] = std::max(radius[bin], p.norm());
      }
    }
    EXPECT_NEAR(fit.surface_error, deviation, 1e-7 * c) << n << " pieces";
    // the balanced polygon errs equally outside (vertices) and inside (chord midpoints)
    EXPECT_NEAR(fit.vertex_radius - c, c - fit.midpoint_radius, 1e-12);

    // inner diameter through the centre: opposite sides less the wire
    double id_min = 1e9, id_max = 0.0;
    for (int bin = 0; bin < kAngles / 2; ++bin) {
      const double across = radius[bin] + radius[bin + kAngles / 2] - 2.0 * a;
      id_min = std::min(id_min, across), id_max = std::max(id_max, across);
    }
    EXPECT_NEAR(fit.inner_diameter_min, id_min, 5e-4 * c) << n << " pieces";
    EXPECT_NEAR(fit.inner_diameter_max, id_max, 5e-4 * c) << n << " pieces";
  }
}

// distance from p to the segment [p0, p1]
double segment_distance(const Vec3& p, const Vec3& p0, const Vec3& p1) {
  const Vec3 d = p1 - p0;
  const double t = std::clamp((p - p0).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p - (p0 + t * d)).norm();
}

TEST(CapsuleTorus, SurfaceErrorMatchesSampledDistanceToTheTorus) {
  const RingGeometry ring;  // WD 1.6 mm, ID 8 mm
  const double a = ring.wire_radius, c = ring.centre_radius;
  for (int pieces : {8, 16, 28, 48}) {
    const auto shape = capsule_torus(a, c, pieces);
    std::vector<Vec3> vertex(pieces);
    for (int k = 0; k < pieces; ++k) {
      const double theta = 2.0 * std::numbers::pi * k / pieces;
      vertex[k] = shape.vertex_radius * Vec3(std::cos(theta), 0.0, std::sin(theta));
    }
    auto compound_distance = [&](const Vec3& p) {
      double d = 1e9;
      for (int k = 0; k < pieces; ++k) {
        d = std::min(d, segment_distance(p, vertex[k], vertex[(k + 1) % pieces]));
      }
      return d - a;  // signed: negative inside the compound
    };
    // distance of true-torus surface points to the compound's surface
    double worst = 0.0;
    for (int u = 0; u < 720; ++u) {
      const double s = 2.0 * std::numbers::pi * (u + 0.37) / 720;
      const Vec3 radial(std::cos(s), 0.0, std::sin(s));
      for (int v = 0; v < 48; ++v) {
        const double t = 2.0 * std::numbers::pi * v / 48;
        const Vec3 p = (c + a * std::cos(t)) * radial + a * std::sin(t) * Vec3::UnitY();
        worst = std::max(worst, std::abs(compound_distance(p)));
      }
    }
    EXPECT_LE(worst, shape.surface_error * (1.0 + 1e-6)) << pieces << " pieces";
    EXPECT_GE(worst, 0.9 * shape.surface_error) << pieces << " pieces";
    // the inner diameter: on the surface across a chord midpoint, in the hole elsewhere
    const double mid = std::numbers::pi / pieces;
    const Vec3 across_midpoint = Vec3(std::cos(mid), 0.0, std::sin(mid));
    EXPECT_NEAR(compound_distance(0.5 * shape.inner_diameter_min * across_midpoint), 0.0, 1e-12);
    for (double s : {0.0, 0.5 * mid, 1.5 * mid}) {
      EXPECT_GT(
          compound_distance(0.5 * shape.inner_diameter_min * Vec3(std::cos(s), 0.0, std::sin(s))),
          0.0);
    }
    EXPECT_LT(shape.inner_diameter_min, ring.inner_diameter());
    EXPECT_NEAR(shape.capsule_length,
                2.0 * shape.vertex_radius * std::sin(std::numbers::pi / pieces), 1e-15);
  }
}

}  // namespace
}  // namespace chainmail

// Bullet rigid-torus backend: torus approximation, free fall in both unit systems, linked rings,
// the catenary of a hanging chain, a hanging curtain and a sheet at rest on a plane (what every
// backend must do is in test_contract.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <numbers>

#include "backend_sim.hpp"
#include "backends/capsule_torus.hpp"
#include "core/metrics.hpp"

namespace chainmail {
namespace {

using nlohmann::json;

class Bullet : public test::BackendTest {
 protected:
  Bullet() : BackendTest("bullet") {}
};

Knobs default_knobs() {
  const Scene scene = scene_from_json(
      {{"name", "defaults"}, {"weave", {{"type", "chain"}, {"cols", 2}}}, {"duration", 1.0}},
      "test");
  return resolve_knobs(scene, *find_backend("bullet"));
}

TEST_F(Bullet, DefaultPiecesKeepErrorUnderTwoPercentOfWireRadius) {
  const RingGeometry ring = RingGeometry::from_diameters(0.0016, 0.008, 7850.0);
  const double a = ring.wire_radius, c = ring.centre_radius;
  const int pieces = static_cast<int>(default_knobs().at("pieces"));
  // the default count keeps the surface within 2 % of the wire radius; fewer pieces would not.
  // The hole's diameter sums the errors of two opposite sides: within 4 % of a (0.4 % of the ID)
  const CapsuleTorus fit = capsule_torus(a, c, pieces);
  EXPECT_LT(fit.surface_error, 0.02 * a);
  EXPECT_GT(capsule_torus(a, c, pieces - 2).surface_error, 0.02 * a);
  EXPECT_LE(fit.inner_diameter_error, 2.0 * fit.surface_error + 1e-12);
  EXPECT_LT(fit.inner_diameter_error, 0.04 * a);
  std::printf(
      "bullet torus, %d capsules: surface error %.2f %% of a, inner diameter error %.2f %% "
      "of a (%.3f %% of ID)\n",
      pieces, 100.0 * fit.surface_error / a, 100.0 * fit.inner_diameter_error / a,
      100.0 * fit.inner_diameter_error / ring.inner_diameter());
}

json single_ring_scene(const json& bullet_knobs) {
  return {{"name", "free_fall"},
          {"weave", {{"type", "4in1"}, {"rows", 1}, {"cols", 1}, {"center", {0.1, 2.0, -0.2}}}},
          {"duration", 1.0},
          {"backends", {{"bullet", bullet_knobs}}}};
}

TEST_F(Bullet, FreeFallMatchesHalfGTSquared) {
  auto run = sim(single_ring_scene({{"linear_damping", 0.0}, {"angular_damping", 0.0}}));
  const Vec3 start = run.frame.position.col(0);
  const Quat rest = run.frame.quat(0);
  const double t = 0.5, g = 9.81;
  run.advance(t);
  ASSERT_NEAR(run.frame.t, t, 1e-12);

  // semi-implicit Euler lags the parabola by g t h / 2 with the internal step h
  const double h = run.dt() / run.knobs.at("substeps");
  const double drop = start.y() - run.frame.position(1, 0);
  EXPECT_NEAR(drop, 0.5 * g * t * t, g * t * h + 1e-5);
  EXPECT_NEAR(run.frame.velocity(1, 0), -g * t, 1e-4 * g * t);
  EXPECT_NEAR(run.frame.position(0, 0), start.x(), 1e-6);
  EXPECT_NEAR(run.frame.position(2, 0), start.z(), 1e-6);
  EXPECT_LT(run.frame.quat(0).angularDistance(rest), 1e-5);  // no torque, no spin
}

TEST_F(Bullet, FreeFallIsTheSameInSiAndScaledUnits) {
  auto scaled = sim(single_ring_scene({{"linear_damping", 0.0}, {"angular_damping", 0.0}}));
  auto si = sim(single_ring_scene(
      {{"linear_damping", 0.0}, {"angular_damping", 0.0}, {"length_scale", 1.0}}));
  ASSERT_NE(scaled.knobs.at("length_scale"), 1.0);
  scaled.advance(0.3);
  si.advance(0.3);
  const double drop = scaled.frame.position(1, 0) - 2.0;
  EXPECT_LT((scaled.frame.position - si.frame.position).norm(), 1e-5 * std::abs(drop));
  EXPECT_LT((scaled.frame.velocity - si.frame.velocity).norm(), 1e-5 * 9.81 * 0.3);
  EXPECT_LT((scaled.frame.orientation - si.frame.orientation).norm(), 1e-6);
}

TEST_F(Bullet, TwoLinkedRingsHangWithoutParting) {
  auto run = sim({{"name", "two_rings"},
                  {"weave", {{"type", "chain"}, {"cols", 2}}},
                  {"pins", {{{"ring", {0, 0}}}}},
                  {"duration", 5.0}});
  const double a = run.scene.ring.wire_radius, id = run.scene.ring.inner_diameter();
  const Vec3 pinned = run.frame.position.col(0);
  double closest = 1e9, farthest = 0.0;
  for (int second = 0; second < 50; ++second) {  // 5 s in 0.1 s samples
    run.advance(0.1);
    ASSERT_TRUE(circles_linked(run.circle(0), run.circle(1))) << "t = " << run.frame.t;
    closest = std::min(closest, circle_circle_distance(run.circle(0), run.circle(1)));
    farthest = std::max(farthest, (run.frame.position.col(1) - run.frame.position.col(0)).norm());
  }
  EXPECT_GE(closest, 2.0 * a - 0.05 * a);
  EXPECT_LE(farthest / id, 1.02);
  EXPECT_EQ((run.frame.position.col(0) - pinned).norm(), 0.0);  // the pin holds exactly
  EXPECT_LT(run.frame.position(1, 1), pinned.y());              // the free ring hangs below
}

TEST_F(Bullet, ChainSagMatchesCatenary) {
  // the bench scene itself: a horizontal chain pinned at both end rings, span 0.75 of its length,
  // damped so that it settles within the scene's duration
  const Scene scene = load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/chain_catenary.json");
  const int kRings = scene.weave.cols;
  auto run = sim(scene_to_json(scene));
  run.advance(scene.duration);

  // catenary through the pinned ring centres with the chain's length (n - 1) ID
  const double span = (run.frame.position.col(kRings - 1) - run.frame.position.col(0)).norm();
  const double length = (kRings - 1) * run.scene.ring.inner_diameter();
  // solve L = 2 A sinh(S / 2A) for A by bisection (the left side falls as A grows)
  double low = 1e-4 * span, high = 1e4 * span;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (low + high);
    (2.0 * mid * std::sinh(span / (2.0 * mid)) > length ? low : high) = mid;
  }
  const double A = 0.5 * (low + high);
  const double expected_sag = A * (std::cosh(span / (2.0 * A)) - 1.0);

  double lowest = 1e9;
  for (int ring = 0; ring < kRings; ++ring) lowest = std::min(lowest, run.frame.position(1, ring));
  const double sag = run.frame.position(1, 0) - lowest;
  RecordProperty("sag_error_percent", std::to_string(100.0 * (sag / expected_sag - 1.0)));
  std::printf("catenary: sag %.5f m, expected %.5f m, error %+.2f %%\n", sag, expected_sag,
              100.0 * (sag / expected_sag - 1.0));
  EXPECT_NEAR(sag, expected_sag, 0.03 * expected_sag);

  const Metrics m = measure(run.frame, run.weave, run.scene);
  EXPECT_EQ(m.broken_links, 0);
  EXPECT_EQ(m.non_finite, 0);
}

TEST_F(Bullet, CurtainHangsWithoutBrokenOrFalseLinks) {
  // the backend's default knobs. Released from the layout, the curtain falls taut within the
  // first quarter second (its longest link then, 0.996 ID, is the run's longest) and hangs at
  // about 0.995 ID after; a second, sampled every quarter, covers the fall and the hang
  auto run = sim({{"name", "curtain"},
                  {"weave", {{"type", "4in1"}, {"rows", 10}, {"cols", 10}, {"plane", "xy"}}},
                  {"pins", {{{"edge", "top"}}}},
                  {"duration", 1.0}});
  for (int k = 0; k < 4; ++k) {
    run.advance(0.25);
    const Metrics m = measure(run.frame, run.weave, run.scene);
    EXPECT_EQ(m.broken_links, 0) << "t = " << run.frame.t;
    EXPECT_EQ(m.false_links, 0) << "t = " << run.frame.t;
    EXPECT_EQ(m.non_finite, 0);
    EXPECT_LT(m.max_stretch, 1.02);
  }
  EXPECT_NEAR(run.frame.t, 1.0, 1e-9);
}

TEST_F(Bullet, SheetRestsOnPlaneWithoutJitter) {
  // a flat 4-in-1 sheet dropped from just above a floor
  auto run =
      sim({{"name", "sheet_on_floor"},
           {"weave", {{"type", "4in1"}, {"rows", 5}, {"cols", 5}, {"center", {0.0, 0.005, 0.0}}}},
           {"colliders", {{{"type", "plane"}, {"point", {0.0, 0.0, 0.0}}, {"friction", 0.5}}}},
           {"duration", 1.0}});
  const RingGeometry& ring = run.scene.ring;
  run.advance(0.5);
  // settled: the kinetic energy stays below that of one ring moving at 1 mm/s, per ring
  const double bound = run.weave.size() * 0.5 * ring.mass() * 1e-6;
  double highest = 0.0;
  for (int k = 0; k < 10; ++k) {
    run.advance(0.05);
    const Metrics m = measure(run.frame, run.weave, run.scene);
    highest = std::max(highest, m.kinetic_energy);
    ASSERT_EQ(m.non_finite, 0);
    for (int r = 0; r < run.weave.size(); ++r) {
      ASSERT_GT(run.frame.position(1, r), 0.0) << "ring " << r << " fell through the floor";
    }
  }
  std::printf("sheet on floor: highest kinetic energy %.3g J, bound %.3g J\n", highest, bound);
  EXPECT_LT(highest, bound);
  EXPECT_EQ(measure(run.frame, run.weave, run.scene).broken_links, 0);
}

}  // namespace
}  // namespace chainmail

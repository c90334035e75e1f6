// ODE rigid-torus backend: the capsule torus, free fall in two unit systems, hanging links, the
// catenary, a pinned curtain and a sheet at rest on a plane.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include <nlohmann/json.hpp>

#include "backend_sim.hpp"
#include "backends/capsule_torus.hpp"
#include "core/metrics.hpp"
#include "physics_oracles.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

class OdeBackend : public test::BackendTest {
 protected:
  OdeBackend() : BackendTest("ode") {}
};
class OdeCapsuleTorus : public OdeBackend {};

json chain_scene(int rings, double spacing, const json& ode_knobs = json::object()) {
  return {{"name", "ode_chain"},
          {"weave", {{"type", "chain"}, {"cols", rings}, {"plane", "xy"}, {"spacing", spacing}}},
          {"duration", 1.0},
          {"backends", {{"ode", ode_knobs}}}};
}

json sheet_scene(int rows, int cols, const std::string& plane,
                 const json& ode_knobs = json::object()) {
  return {{"name", "ode_sheet"},
          {"weave", {{"type", "4in1"}, {"rows", rows}, {"cols", cols}, {"plane", plane}}},
          {"duration", 1.0},
          {"backends", {{"ode", ode_knobs}}}};
}

// ---------------------------------------------------------------------------------------------
// the capsule torus

TEST_F(OdeCapsuleTorus, DefaultPiecesKeepErrorUnderTwoPercentOfWireRadius) {
  const RingGeometry ring;
  const BackendInfo* info = find_backend("ode");
  ASSERT_NE(info, nullptr);
  const Knobs knobs = resolve_knobs(scene_from_json(sheet_scene(1, 1, "xz"), "test"), *info);
  const int pieces = static_cast<int>(knobs.at("pieces"));
  const auto shape = capsule_torus(ring.wire_radius, ring.centre_radius, pieces);
  const double error = shape.surface_error / ring.wire_radius;
  const double id_error = (ring.inner_diameter() - shape.inner_diameter_min) / ring.wire_radius;
  std::printf("[ode] %d pieces: surface error %.4f a, inner diameter %.4f a short (%.3f %% ID)\n",
              pieces, error, id_error, 100.0 * id_error * ring.wire_radius / ring.inner_diameter());
  EXPECT_LT(error, 0.02);
  EXPECT_LT(id_error, 0.04);
  // one piece fewer per quarter would not do: the default is not wastefully large
  const auto coarser = capsule_torus(ring.wire_radius, ring.centre_radius, pieces - 4);
  EXPECT_GT(coarser.surface_error / ring.wire_radius, 0.02);
}

// ---------------------------------------------------------------------------------------------
// knobs

TEST_F(OdeBackend, DeclaresItsKnobsAndRefusesBadValues) {
  const BackendInfo* info = find_backend("ode");
  ASSERT_NE(info, nullptr);
  for (const char* knob :
       {"dt", "substeps", "iterations", "erp", "cfm", "restitution", "linear_damping",
        "angular_damping", "pieces", "length_scale", "max_contacts"}) {
    EXPECT_NE(find_knob(*info, knob), nullptr) << knob;
  }
  for (const json& bad : {json{{"pieces", 2}}, json{{"length_scale", -1.0}},
                          json{{"iterations", 0}}, json{{"erp", 1.5}}, json{{"nonsense", 1}}}) {
    const Scene scene = scene_from_json(sheet_scene(1, 1, "xz", bad), "test");
    EXPECT_THROW(resolve_knobs(scene, *info), SceneError) << bad.dump();
  }
}

// ---------------------------------------------------------------------------------------------
// free fall

TEST_F(OdeBackend, FreeFallMatchesHalfGTSquared) {
  auto run = sim(sheet_scene(1, 1, "xz"));
  const Vec3 start = run.frame.position.col(0);
  const Quat rest = run.frame.quat(0);
  const double t = 0.5, g = 9.81;
  run.advance(t);
  EXPECT_NEAR(run.frame.t, t, 1e-12);
  const Vec3 fell = run.frame.position.col(0) - start;
  // semi-implicit Euler lags the exact parabola by g h t / 2 for a solver step h
  const double h = run.dt() / run.knobs.at("substeps");
  EXPECT_NEAR(fell.y(), -0.5 * g * t * t, g * h * t);
  EXPECT_NEAR(fell.x(), 0.0, 1e-12);
  EXPECT_NEAR(fell.z(), 0.0, 1e-12);
  EXPECT_NEAR(run.frame.velocity(1, 0), -g * t, 1e-9);
  EXPECT_LT(run.frame.quat(0).angularDistance(rest), 1e-9);
}

TEST_F(OdeBackend, FreeFallIsTheSameInMetresAndInternalUnits) {
  auto scaled = sim(sheet_scene(1, 1, "xz"));
  auto metres = sim(sheet_scene(1, 1, "xz", {{"length_scale", 1.0}}));
  ASSERT_NE(scaled.knobs.at("length_scale"), 1.0);
  scaled.advance(0.3);
  metres.advance(0.3);
  EXPECT_NEAR((scaled.frame.position.col(0) - metres.frame.position.col(0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((scaled.frame.velocity.col(0) - metres.frame.velocity.col(0)).norm(), 0.0, 1e-12);
  EXPECT_LT(scaled.frame.quat(0).angularDistance(metres.frame.quat(0)), 1e-9);
}

// ---------------------------------------------------------------------------------------------
// links

TEST_F(OdeBackend, TwoLinkedRingsHangLinkedWithoutInterpenetration) {
  json document = chain_scene(2, 0.9);
  document["pins"] = {{{"ring", {0, 0}}}};
  document["gravity"] = {0.0, -9.81, 0.0};
  auto run = sim(document);
  const RingGeometry& ring = run.scene.ring;
  const Vec3 pinned = run.frame.position.col(0);
  double worst_gap = 1e9, worst_stretch = 0.0;
  for (int sample = 0; sample < 100; ++sample) {
    run.advance(0.05);
    ASSERT_TRUE(circles_linked(run.circle(0), run.circle(1))) << "t = " << run.frame.t;
    worst_gap = std::min(worst_gap, circle_circle_distance(run.circle(0), run.circle(1)));
    worst_stretch =
        std::max(worst_stretch, (run.frame.position.col(1) - run.frame.position.col(0)).norm() /
                                    ring.inner_diameter());
  }
  EXPECT_NEAR(run.frame.t, 5.0, 1e-9);
  EXPECT_EQ(run.frame.position.col(0), pinned);  // a pin does not move
  EXPECT_GE(worst_gap, 2.0 * ring.wire_radius - 0.05 * ring.wire_radius);
  EXPECT_LE(worst_stretch, 1.02);
  // the free ring hangs below its pin, pulled out to (nearly) the full link length
  EXPECT_LT(run.frame.position(1, 1), pinned.y() - 0.9 * ring.inner_diameter());
  std::printf("[ode] two rings, 5 s: closest wire centres %.4f a (2a touching), stretch %.4f\n",
              worst_gap / ring.wire_radius, worst_stretch);
}

using test::catenary_sag;

TEST_F(OdeBackend, ChainHangsAsACatenary) {
  // the bench scene itself (its damping only speeds up settling; the equilibrium does not
  // depend on it)
  const Scene scene = load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/chain_catenary.json");
  const int rings = scene.weave.cols;
  auto run = sim(scene);
  const double inner = run.scene.ring.inner_diameter();
  const double span = (run.frame.position.col(rings - 1) - run.frame.position.col(0)).norm();
  const double length = (rings - 1) * inner;
  const double expected = catenary_sag(span, length);
  const double pin_height = run.frame.position(1, 0);

  auto sag_now = [&] { return pin_height - run.frame.position.row(1).minCoeff(); };
  run.advance(scene.duration - 1.0);
  const double sag_before = sag_now();
  run.advance(1.0);
  const Metrics m = measure(run.frame, run.weave, run.scene);
  const double sag = sag_now();
  std::printf(
      "[ode] catenary, %d rings: sag %.2f mm, expected %.2f mm (%+.2f %%), KE %.3g J, "
      "max speed %.3g m/s, max stretch %.4f\n",
      rings, 1e3 * sag, 1e3 * expected, 100.0 * (sag - expected) / expected, m.kinetic_energy,
      m.max_speed, m.max_stretch);
  EXPECT_EQ(m.non_finite, 0);
  EXPECT_EQ(m.broken_links, 0);
  EXPECT_EQ(m.false_links, 0);
  EXPECT_NEAR(sag, expected, 0.03 * expected);
  // settled: the shape holds still and what motion is left (QuickStep's residual jitter, about
  // 1 cm/s at the default iterations) is tiny against the potential energy the chain gave up
  EXPECT_NEAR(sag, sag_before, 0.005 * expected);
  const double released = rings * run.scene.ring.mass() * 9.81 * expected;
  EXPECT_LT(m.kinetic_energy, 1e-4 * released);
}

TEST_F(OdeBackend, CurtainKeepsItsLinks) {
  json document = sheet_scene(10, 10, "xy");
  document["pins"] = {{{"edge", "top"}}};
  auto run = sim(document);
  for (int sample = 0; sample < 4; ++sample) {
    run.advance(0.5);
    const Metrics m = measure(run.frame, run.weave, run.scene);
    EXPECT_EQ(m.non_finite, 0) << "t = " << run.frame.t;
    EXPECT_EQ(m.broken_links, 0) << "t = " << run.frame.t;
    EXPECT_EQ(m.false_links, 0) << "t = " << run.frame.t;
    EXPECT_LE(m.max_stretch, 1.02) << "t = " << run.frame.t;
    if (sample == 3) {
      std::printf(
          "[ode] curtain 10x10, 2 s: max stretch %.4f, penetrating linked %lld other %lld\n",
          m.max_stretch, m.penetrating_linked, m.penetrating_other);
    }
  }
  // the curtain hangs: its lowest ring is well below the pinned row
  EXPECT_LT(run.frame.position.row(1).minCoeff(),
            run.frame.position(1, 0) - 8.0 * run.scene.ring.inner_diameter() * 0.7);
}

TEST_F(OdeBackend, SheetComesToRestOnAPlane) {
  json document = sheet_scene(6, 6, "xz");
  document["weave"]["center"] = {0.0, 0.005, 0.0};
  document["colliders"] = {{{"type", "plane"}, {"point", {0.0, 0.0, 0.0}}, {"friction", 0.5}}};
  auto run = sim(document);
  const RingGeometry& ring = run.scene.ring;
  run.advance(1.0);  // fall 1.5 mm and settle
  double worst_energy = 0.0, lowest = 1e9;
  for (int sample = 0; sample < 20; ++sample) {
    run.advance(0.05);
    const Metrics m = measure(run.frame, run.weave, run.scene);
    ASSERT_EQ(m.non_finite, 0);
    worst_energy = std::max(worst_energy, m.kinetic_energy);
    lowest = std::min(lowest, run.frame.position.row(1).minCoeff());
  }
  // bound: every ring moving at 5 mm/s
  const double bound = run.frame.size() * 0.5 * ring.mass() * 0.005 * 0.005;
  std::printf("[ode] sheet on plane: worst KE %.3g J (bound %.3g J), lowest centre %.3f mm\n",
              worst_energy, bound, 1e3 * lowest);
  EXPECT_LT(worst_energy, bound);
  EXPECT_GT(lowest, ring.wire_radius * 0.9);  // lying on the plane, not through it
  EXPECT_LT(lowest, 0.005);                   // and it did come down
}

// ---------------------------------------------------------------------------------------------
// failure, stages

TEST_F(OdeBackend, AnUnstableRunEndsCleanly) {
  // knobs far outside their useful range: huge gravity, one coarse step, no error correction cap
  json document = sheet_scene(4, 4, "xy",
                              {{"dt", 0.05},
                               {"substeps", 1},
                               {"iterations", 1},
                               {"erp", 1.0},
                               {"cfm", 0.0},
                               {"restitution", 1.0},
                               {"max_correcting_velocity", 0.0}});
  document["pins"] = {{{"corner", "top_left"}}};
  document["gravity"] = {3000.0, -9000.0, 5000.0};
  auto run = sim(document);
  run.advance(1.0);
  EXPECT_NEAR(run.frame.t, 1.0, 1e-9);  // time runs on whatever the state
  const Metrics m = measure(run.frame, run.weave, run.scene);
  std::printf("[ode] unstable run: %lld non-finite entries, max speed %.3g m/s\n", m.non_finite,
              m.max_speed);
  // either the state is finite or it is reported as non-finite as a whole; nothing else
  EXPECT_TRUE(m.non_finite == 0 || m.non_finite == 10 * run.frame.size()) << m.non_finite;
  // and the step says which
  EXPECT_EQ(run.status == StepStatus::non_finite, m.non_finite > 0);
}

TEST_F(OdeBackend, DampingRateHoldsForAnyStep) {
  // a lone ring coasting in zero gravity loses speed as exp(-rate t) whatever step it is taken
  // with: ODE's per-step factor is derived from the step actually taken, not from the dt knob
  const double rate = 2.0, t = 0.5, v0 = 0.1;  // 1/s, s, m/s
  json document = sheet_scene(1, 1, "xz", {{"linear_damping", rate}});
  document["gravity"] = {0.0, 0.0, 0.0};
  document["initial_velocity"] = {v0, 0.0, 0.0};
  for (const double step : {1e-3, 2e-3, 5e-4}) {
    auto run = sim(document);
    const long long count = std::llround(t / step);
    for (long long k = 0; k < count; ++k) run.backend->step(step);
    run.backend->frame(run.frame);
    // the factors multiply exactly: only rounding separates the product from the exponential
    EXPECT_NEAR(run.frame.velocity(0, 0), v0 * std::exp(-rate * t), 1e-9 * v0) << step;
  }
}

TEST_F(OdeBackend, StagesFollowTheScene) {
  auto run = sim(sheet_scene(2, 2, "xz"));
  run.advance(0.01);
  const auto& stages = run.backend->profile().stages();
  EXPECT_TRUE(stages.count("ring_contact"));
  EXPECT_TRUE(stages.count("solve"));
  EXPECT_FALSE(stages.count("colliders"));  // no colliders in the scene: the stage never runs
}

}  // namespace
}  // namespace chainmail

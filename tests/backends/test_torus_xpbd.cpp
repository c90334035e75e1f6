// The torus_xpbd backend: its knobs, the 10 m/s impact that tears the rigid references, a hanging
// curtain's links (held, within 0.02 a of touching) and the catenary's sag.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "backend_sim.hpp"
#include "core/metrics.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

class TorusXpbd : public test::BackendTest {
 protected:
  TorusXpbd() : BackendTest("torus_xpbd") {}
};

json sheet(int rows, int cols, const std::string& plane, const json& knobs = json::object()) {
  return {{"name", "xpbd_sheet"},
          {"weave", {{"type", "4in1"}, {"rows", rows}, {"cols", cols}, {"plane", plane}}},
          {"duration", 1.0},
          {"backends", {{"torus_xpbd", knobs}}}};
}

TEST_F(TorusXpbd, DeclaresItsKnobsAndRefusesBadValues) {
  const BackendInfo* info = find_backend("torus_xpbd");
  ASSERT_NE(info, nullptr);
  for (const char* knob :
       {"dt", "substeps", "friction", "restitution", "compliance", "damping", "sleeping"}) {
    EXPECT_NE(find_knob(*info, knob), nullptr) << knob;
  }
  EXPECT_EQ(find_knob(*info, "sleeping")->default_value, 0.0) << "sleeping is off by default";
  EXPECT_EQ(find_knob(*info, "compliance")->default_value, 0.0) << "rigid by default";
  for (const json& bad :
       {json{{"substeps", 0}}, json{{"restitution", 1.5}}, json{{"friction", -1.0}},
        json{{"sleeping", 1}}, json{{"iterations", 4}}}) {
    const Scene scene = scene_from_json(sheet(1, 1, "xz", bad), "test");
    EXPECT_THROW(resolve_knobs(scene, *info), SceneError) << bad.dump();
  }
}

TEST_F(TorusXpbd, TheTenMetrePerSecondImpactHoldsAtTheDefaultStep) {
  // the stability suite's impact: a sheet hitting a sphere at 10 m/s, where Bullet and ODE tear;
  // fast rings take more substeps, so no wire passes through another
  auto run = sim(load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/stability/impact.json"));
  EXPECT_EQ(run.dt(), 0.005);
  double fastest = 0.0;
  for (int sample = 0; sample < 10; ++sample) {
    run.advance(0.02);
    ASSERT_EQ(run.status, StepStatus::ok);
    const Metrics m = measure(run.frame, run.weave, run.scene);
    ASSERT_EQ(m.broken_links, 0) << "t = " << run.frame.t;
    EXPECT_EQ(m.false_links, 0) << "t = " << run.frame.t;
    EXPECT_LE(m.max_stretch, 1.0 + 1e-3) << "t = " << run.frame.t;
    fastest = std::max(fastest, m.max_speed);
  }
  EXPECT_LT(fastest, run.scene.stability.max_speed);
}

TEST_F(TorusXpbd, AHangingCurtainHoldsItsLinksWithinTwoHundredthsOfTheWireRadius) {
  json document = sheet(6, 6, "xy");
  document["pins"] = {{{"edge", "top"}}};
  auto run = sim(document);
  run.advance(0.6);
  const Metrics m = measure(run.frame, run.weave, run.scene);
  EXPECT_EQ(m.broken_links, 0);
  EXPECT_EQ(m.false_links, 0);
  const double a = run.scene.ring.wire_radius;
  std::printf("[torus_xpbd] 6x6 curtain: deepest linked %.4f a, other %.4f a, stretch %.4f\n",
              m.penetration_max_linked / a, m.penetration_max_other / a, m.max_stretch);
  EXPECT_LE(m.penetration_max_linked, 0.02 * a);
  EXPECT_LE(m.penetration_max_other, 0.02 * a);
  // links no longer than the straight hook allows
  EXPECT_LE(m.max_stretch, 1.0 + 1e-3);
  // the links carry the sheet: it hangs at rest
  EXPECT_LT(m.max_speed, 0.01);
}

TEST_F(TorusXpbd, TheCatenarySagsWithinOnePercent) {
  // the bench's 60-ring chain between two pins, damped by the scene so that it settles
  auto run = sim(load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/chain_catenary.json"));
  run.advance(run.scene.duration);
  const std::optional<double> error = catenary_error(run.scene, run.weave, run.frame);
  ASSERT_TRUE(error.has_value());
  std::printf("[torus_xpbd] catenary sag error %.3f %%\n", 100.0 * *error);
  EXPECT_LT(std::abs(*error), 0.01);
}

}  // namespace
}  // namespace chainmail

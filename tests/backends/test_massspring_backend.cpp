// The massspring backend: knobs, the cloth scenes, stages that run, surface-following frames
// (what every backend must do is in test_contract.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "backend_sim.hpp"

namespace chainmail {
namespace {

const std::string kClothDir = std::string(CHAINMAIL_SOURCE_DIR) + "/bench/scenes/cloth/";

const BackendInfo& info() {
  const BackendInfo* found = find_backend("massspring");
  EXPECT_NE(found, nullptr);
  return *found;
}

test::BackendSim massspring(const Scene& scene) {
  return test::BackendSim("massspring", scene);
}

// a small 4-in-1 sheet hanging from its top edge; knobs as given
Scene mail_scene(const nlohmann::json& knobs, bool self_contact, bool floor) {
  nlohmann::json doc = {{"name", "mail"},
                        {"weave", {{"type", "4in1"}, {"rows", 8}, {"cols", 8}, {"plane", "xy"}}},
                        {"pins", {{{"edge", "top"}}}},
                        {"duration", 0.5},
                        {"features", {{"self_contact", self_contact}}},
                        {"reference", "massspring"},
                        {"backends", {{"massspring", knobs}}}};
  if (floor) {
    doc["colliders"] = {{{"type", "plane"}, {"point", {0.0, -0.03, 0.0}}, {"normal", {0, 1, 0}}}};
  }
  return scene_from_json(doc, "mail.json");
}

Vec3 axis_of(const RingFrame& f, int ring) {
  return f.quat(ring) * Vec3::UnitY();
}
Vec3 local_x_of(const RingFrame& f, int ring) {
  return f.quat(ring) * Vec3::UnitX();
}

TEST(MassSpringBackend, RegisteredWithTheDocumentsKnobs) {
  const BackendInfo& b = info();
  EXPECT_EQ(b.name, "massspring");
  for (const char* knob : {"dt", "substeps", "ks", "shear_ks", "bend_ks", "damping_percent",
                           "correction_passes", "max_extension", "thickness", "areal_density"}) {
    EXPECT_NE(find_knob(b, knob), nullptr) << knob;
  }
  const Knobs defaults = resolve_knobs(mail_scene(nlohmann::json::object(), false, false), b);
  EXPECT_DOUBLE_EQ(defaults.at("dt"), 1.0 / 2700.0);
  EXPECT_EQ(defaults.at("correction_passes"), 1.0);
  EXPECT_EQ(defaults.at("max_extension"), 0.1);
  EXPECT_EQ(defaults.at("areal_density"), 0.0);
  EXPECT_THROW(resolve_knobs(mail_scene({{"stiffness", 1.0}}, false, false), b), SceneError);
  EXPECT_THROW(resolve_knobs(mail_scene({{"damping_percent", 150.0}}, false, false), b),
               SceneError);
}

TEST(MassSpringBackend, ClothScenesLoadAndListOnlyThisBackend) {
  int count = 0;
  for (const char* name : {"pinned2", "pinned4", "sphere", "plane", "selfcollision"}) {
    SCOPED_TRACE(name);
    const Scene scene = load_scene_file(kClothDir + name + ".json");
    EXPECT_NO_THROW(validate_backend_knobs(scene));
    EXPECT_EQ(scene.weave.type, WeaveType::grid);
    EXPECT_EQ(scene.weave.rows * scene.weave.cols, 2500);
    EXPECT_NEAR(scene.weave.spacing * 49.0, 1.0, 1e-12);
    ASSERT_EQ(scene.backends.size(), 1u);
    const Knobs knobs = resolve_knobs(scene, info());
    EXPECT_DOUBLE_EQ(knobs.at("dt"), 1.0 / 2700.0);
    EXPECT_EQ(knobs.at("ks"), 5000.0);
    EXPECT_EQ(knobs.at("damping_percent"), 0.2);
    EXPECT_EQ(knobs.at("thickness"), 0.0095);
    ++count;
  }
  // every file of the folder is one of them
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kClothDir)) {
    files += entry.path().extension() == ".json";
  }
  EXPECT_EQ(files, count);
}

TEST(MassSpringBackend, RestFrameFollowsTheSheet) {
  const Scene scene = load_scene_file(kClothDir + "pinned2.json");
  auto run = massspring(scene);
  const RingFrame f = run.frame;
  ASSERT_EQ(f.size(), 2500);
  EXPECT_EQ(f.t, 0.0);
  for (int m = 0; m < f.size(); ++m) {
    EXPECT_NEAR(f.orientation.col(m).norm(), 1.0, 1e-12);
    EXPECT_GT(axis_of(f, m).dot(run.weave.normal_axis), 1.0 - 1e-12);
    EXPECT_GT(local_x_of(f, m).dot(run.weave.row_axis), 1.0 - 1e-12);
    EXPECT_EQ(f.velocity.col(m).norm(), 0.0);
  }
}

TEST(MassSpringBackend, RingAxisIsTheSurfaceNormalAsTheClothMoves) {
  const Scene scene = load_scene_file(kClothDir + "pinned2.json");
  auto run = massspring(scene);
  run.steps(1350);  // half a second: swinging down
  const RingFrame f = run.frame;
  EXPECT_GT(f.t, 0.49);
  int checked = 0;
  for (int m = 0; m < f.size(); ++m) {
    const auto& nb = run.weave.neighbours[m];
    if (nb[0] < 0 || nb[1] < 0 || nb[2] < 0 || nb[3] < 0) continue;
    const Vec3 u = f.position.col(nb[1]) - f.position.col(nb[0]);
    const Vec3 v = f.position.col(nb[3]) - f.position.col(nb[2]);
    const Vec3 axis = axis_of(f, m);
    // along the normal of the neighbour vectors (up to the local curvature), X along the row
    EXPECT_GT(axis.dot(v.cross(u).normalized()), 0.999);
    EXPECT_NEAR(axis.dot(u.normalized()), 0.0, 0.03);
    EXPECT_GT(local_x_of(f, m).dot(u.normalized()), 0.999);
    ++checked;
  }
  EXPECT_EQ(checked, 48 * 48);
  // the cloth has swung: its normals are no longer vertical
  EXPECT_LT(axis_of(f, 1250).dot(Vec3::UnitY()), 0.9);
}

TEST(MassSpringBackend, MailSheetRestOrientationIsFlatWithNoSwivel) {
  // the default springs, derived from the sheet, and the substeps they need
  auto run = massspring(mail_scene(nlohmann::json::object(), false, false));
  const RingFrame f = run.frame;
  for (int m = 0; m < f.size(); ++m) {
    EXPECT_GT(axis_of(f, m).dot(run.weave.normal_axis), 1.0 - 1e-9) << m;
  }
  run.steps(300);
  // hanging from its top edge, the sheet sags but stays a sheet: no flipped normals
  const RingFrame later = run.frame;
  for (int m = 0; m < later.size(); ++m) {
    EXPECT_GT(axis_of(later, m).dot(run.weave.normal_axis), 0.5) << m;
    EXPECT_TRUE(later.position.col(m).allFinite());
  }
}

TEST(MassSpringBackend, StagesForLeftOutFeaturesNeverRun) {
  auto plain = massspring(mail_scene(nlohmann::json::object(), false, false));
  plain.steps(10);
  const auto& stages = plain.profile().stages();
  EXPECT_EQ(stages.at("forces").calls, 10);
  EXPECT_EQ(stages.at("integrate").calls, 10);
  EXPECT_EQ(stages.count("colliders"), 0u);
  EXPECT_EQ(stages.count("self_contact"), 0u);

  auto all = massspring(mail_scene({{"substeps", 3}}, true, true));
  all.steps(10);
  const auto& more = all.profile().stages();
  EXPECT_EQ(more.at("forces").calls, 30);
  EXPECT_GT(more.at("colliders").calls, 0);
  EXPECT_GT(more.at("self_contact").calls, 0);
  EXPECT_NEAR(all.frame.t, 10.0 / 2700.0, 1e-15);
}

TEST(MassSpringBackend, RingMassByDefaultArealDensityWhenGiven) {
  // a lighter or heavier sheet sags differently under the same springs
  auto ring_mass =
      massspring(mail_scene({{"ks", 5.0}, {"shear_ks", 5.0}, {"bend_ks", 1.0}}, false, false));
  auto heavy = massspring(mail_scene(
      {{"ks", 5.0}, {"shear_ks", 5.0}, {"bend_ks", 1.0}, {"areal_density", 50.0}}, false, false));
  ring_mass.steps(200);
  heavy.steps(200);
  const double light_y = ring_mass.frame.position.row(1).mean();
  const double heavy_y = heavy.frame.position.row(1).mean();
  EXPECT_LT(heavy_y, light_y - 1e-4);
}

TEST(MassSpringBackend, SameSceneTwiceSameHash) {
  const Scene scene = load_scene_file(kClothDir + "selfcollision.json");
  auto a = massspring(scene);
  auto b = massspring(scene);
  a.steps(600);
  b.steps(600);
  EXPECT_EQ(frame_hash(a.frame), frame_hash(b.frame));
}

}  // namespace
}  // namespace chainmail

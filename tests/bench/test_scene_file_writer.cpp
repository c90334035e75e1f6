#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "scene_documents.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

using test::minimal_scene;

std::set<std::string> keys_of(const json& object) {
  std::set<std::string> keys;
  for (auto it = object.begin(); it != object.end(); ++it) keys.insert(it.key());
  return keys;
}

// every key the file gives has the same value in the written scene (numbers compared as numbers)
void expect_contains(const json& written, const json& given, const std::string& path) {
  if (given.is_object()) {
    ASSERT_TRUE(written.is_object()) << path;
    for (auto it = given.begin(); it != given.end(); ++it) {
      if (path.empty() && it.key() == "pins") continue;  // a ring index is written as [row, col]
      ASSERT_TRUE(written.contains(it.key())) << path << "." << it.key();
      expect_contains(written[it.key()], *it, path + "." + it.key());
    }
  } else if (given.is_array()) {
    ASSERT_TRUE(written.is_array()) << path;
    ASSERT_EQ(written.size(), given.size()) << path;
    for (size_t k = 0; k < given.size(); ++k) {
      expect_contains(written[k], given[k], path + "[" + std::to_string(k) + "]");
    }
  } else {
    EXPECT_EQ(written, given) << path;
  }
}

// the fields the models, metrics and the harness read, compared exactly
void expect_same_scene(const Scene& a, const Scene& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.description, b.description);
  EXPECT_EQ(a.ring.wire_radius, b.ring.wire_radius);
  EXPECT_EQ(a.ring.centre_radius, b.ring.centre_radius);
  EXPECT_EQ(a.ring.density, b.ring.density);
  EXPECT_EQ(a.ring_friction, b.ring_friction);
  EXPECT_EQ(a.weave.type, b.weave.type);
  EXPECT_EQ(a.weave.rows, b.weave.rows);
  EXPECT_EQ(a.weave.cols, b.weave.cols);
  EXPECT_EQ(a.weave.plane, b.weave.plane);
  EXPECT_EQ(a.weave.center, b.weave.center);
  EXPECT_EQ(a.weave.spacing, b.weave.spacing);
  ASSERT_EQ(a.pins.size(), b.pins.size());
  for (size_t k = 0; k < a.pins.size(); ++k) {
    EXPECT_EQ(a.pins[k].kind, b.pins[k].kind) << k;
    EXPECT_EQ(a.pins[k].which, b.pins[k].which) << k;
    EXPECT_TRUE(a.pins[k].row == b.pins[k].row && a.pins[k].col == b.pins[k].col) << k;
  }
  ASSERT_EQ(a.colliders.size(), b.colliders.size());
  for (size_t k = 0; k < a.colliders.size(); ++k) {
    const Collider &p = a.colliders[k], &q = b.colliders[k];
    EXPECT_TRUE(p.type == q.type && p.center == q.center && p.normal == q.normal &&
                p.radius == q.radius && p.half_extents == q.half_extents &&
                p.half_height == q.half_height && p.friction == q.friction)
        << k;
  }
  ASSERT_EQ(a.support.has_value(), b.support.has_value());
  if (a.support) {
    EXPECT_TRUE(a.support->center == b.support->center);
    EXPECT_EQ(a.support->radius, b.support->radius);
  }
  ASSERT_EQ(a.loads.size(), b.loads.size());
  for (size_t k = 0; k < a.loads.size(); ++k) {
    EXPECT_TRUE(a.loads[k].row == b.loads[k].row && a.loads[k].col == b.loads[k].col &&
                a.loads[k].mass_factor == b.loads[k].mass_factor)
        << k;
  }
  EXPECT_EQ(a.initial_velocity, b.initial_velocity);
  EXPECT_EQ(a.gravity, b.gravity);
  EXPECT_EQ(a.duration, b.duration);
  EXPECT_EQ(a.sample_interval, b.sample_interval);
  EXPECT_EQ(a.self_contact, b.self_contact);
  EXPECT_EQ(a.write_frames, b.write_frames);
  EXPECT_EQ(a.camera.automatic, b.camera.automatic);
  EXPECT_TRUE(a.camera.position == b.camera.position && a.camera.target == b.camera.target);
  EXPECT_EQ(a.camera.fov_deg, b.camera.fov_deg);
  EXPECT_TRUE(a.stability.max_speed == b.stability.max_speed &&
              a.stability.links_must_hold == b.stability.links_must_hold &&
              a.stability.max_stretch == b.stability.max_stretch &&
              a.stability.energy_growth == b.stability.energy_growth);
  EXPECT_EQ(a.reference, b.reference);
  EXPECT_EQ(a.reference_dt, b.reference_dt);
  ASSERT_EQ(a.backends.size(), b.backends.size());
  for (const auto& [backend, knobs] : a.backends) {
    ASSERT_TRUE(b.backends.count(backend)) << backend;
    const KnobSection& other = b.backends.at(backend);
    ASSERT_EQ(knobs.size(), other.size()) << backend;
    for (const auto& [name, knob] : knobs) {
      ASSERT_TRUE(other.count(name)) << backend << "." << name;
      EXPECT_EQ(knob.kind, other.at(name).kind) << backend << "." << name;
      EXPECT_EQ(knob.value, other.at(name).value) << backend << "." << name;
      EXPECT_EQ(knob.text, other.at(name).text) << backend << "." << name;
    }
  }
}

TEST(SceneWriter, MinimalSceneIsWrittenWithEveryDefault) {
  const json written = scene_to_json(scene_from_json(minimal_scene(), "scene.json"));
  EXPECT_EQ(keys_of(written),
            (std::set<std::string>{"name", "description", "ring", "weave", "pins", "colliders",
                                   "initial_velocity", "gravity", "duration", "sample_interval",
                                   "features", "output", "camera", "stability", "reference",
                                   "reference_dt", "backends"}));
  EXPECT_EQ(written["ring"].dump(),
            R"({"density":7850.0,"friction":0.3,"inner_diameter":0.008,"wire_diameter":0.0016})");
  EXPECT_EQ(written["weave"].dump(),
            R"({"center":[0.0,0.0,0.0],"cols":5,"plane":"xz","rows":4,"type":"4in1"})");
  EXPECT_EQ(written["camera"].dump(), R"({"fov_deg":40.0})");  // automatic: no position/target
  EXPECT_EQ(written["stability"].dump(),
            R"({"energy_growth":1.5,"links_must_hold":true,"max_speed":20.0,"max_stretch":1.25})");
  EXPECT_EQ(written["duration"].dump(), "0.1");
  EXPECT_EQ(written["reference"], "bullet");
  EXPECT_EQ(written["pins"], json::array());
  EXPECT_EQ(written["backends"], json::object());
}

TEST(SceneWriter, FormsAreTheReadersOwn) {
  json doc = minimal_scene();
  doc["weave"] = {{"type", "chain"}, {"cols", 6}};
  doc["pins"] = json::array({{{"ring", 4}}, {{"ring", {0, 5}}}, {{"corner", "top_left"}}});
  doc["camera"] = {{"target", {0, 0.1, 0}}};
  doc["loads"] = json::array({{{"ring", {0, 2}}, {"mass_factor", 3}}});
  doc["support"] = {{"center", {0, -0.1, 0}}, {"radius", 0.05}};
  const json written = scene_to_json(scene_from_json(doc, "scene.json"));
  EXPECT_EQ(written["pins"].dump(), R"([{"ring":[0,4]},{"ring":[0,5]},{"corner":"top_left"}])");
  EXPECT_EQ(written["weave"]["rows"], 1);
  EXPECT_EQ(written["weave"]["spacing"], 0.9);  // a chain's default spacing
  // one of position/target fixes the camera: both are written
  EXPECT_EQ(written["camera"].dump(),
            R"({"fov_deg":40.0,"position":[0.0,0.5,1.0],"target":[0.0,0.1,0.0]})");
  EXPECT_EQ(written["loads"].dump(), R"([{"mass_factor":3.0,"ring":[0,2]}])");
  EXPECT_EQ(written["support"].dump(), R"({"center":[0.0,-0.1,0.0],"radius":0.05})");
}

TEST(SceneWriter, KnobSectionsAsWritten) {
  json doc = minimal_scene();
  doc["backends"] = {{"massspring", {{"substeps", 10}, {"ks", 500.0}, {"dt", 1e-3}}},
                     {"plausible", {{"swivel_fit", true}, {"iterations", -3}}},
                     {"ode", json::object()},
                     {"torus_xpbd", {{"friction_law", "pyramid"}}}};
  const Scene scene = scene_from_json(doc, "scene.json");
  const json written = scene_to_json(scene);
  // a choice's name as given, and read back the same
  EXPECT_EQ(written["backends"].dump(),
            R"({"massspring":{"dt":0.001,"ks":500.0,"substeps":10},"ode":{},)"
            R"("plausible":{"iterations":-3,"swivel_fit":true},)"
            R"("torus_xpbd":{"friction_law":"pyramid"}})");
  const Scene read = scene_from_json(written, "written.json");
  const KnobValue& law = read.backends.at("torus_xpbd").at("friction_law");
  EXPECT_EQ(law.kind, KnobValue::Kind::string);
  EXPECT_EQ(law.text, "pyramid");
  EXPECT_EQ(scene.backends.at("torus_xpbd").at("friction_law").text, "pyramid");
}

// values the reader transforms are written as given, so the written scene reads back bit for bit
TEST(SceneWriter, GivenNormalAndInnerDiameterAreWrittenAsGiven) {
  json doc = minimal_scene();
  doc["ring"] = {{"inner_diameter", 0.0071}};  // 2(c - a) is 0.007100000000000001
  doc["colliders"] = json::array({{{"type", "plane"}, {"normal", {0.0, 1.0, 0.05}}}});
  const Scene scene = scene_from_json(doc, "scene.json");
  ASSERT_NE(scene.ring.inner_diameter(), 0.0071);
  const json written = scene_to_json(scene);
  EXPECT_EQ(written["ring"]["inner_diameter"].get<double>(), 0.0071);
  EXPECT_EQ(written["colliders"][0]["normal"], json({0.0, 1.0, 0.05}));
  expect_same_scene(scene, scene_from_json(written, "summary.json"));
  // a scene built in code has only the unit normal and the radii: those are written
  Scene built = scene;
  built.colliders[0].normal = Vec3(1.0, 0.0, 0.0);
  built.ring = RingGeometry::from_diameters(0.002, 0.01, 7000.0);
  const json rewritten = scene_to_json(built);
  EXPECT_EQ(rewritten["colliders"][0]["normal"], json({1.0, 0.0, 0.0}));
  EXPECT_EQ(rewritten["ring"]["inner_diameter"].get<double>(), built.ring.inner_diameter());
  EXPECT_EQ(rewritten["ring"]["density"].get<double>(), 7000.0);
}

// load, write, load, write: the two documents are equal, the two scenes agree, and every key the
// file gives is written with its value
TEST(SceneWriter, EveryBenchSceneRoundTrips) {
  int count = 0;
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(CHAINMAIL_SOURCE_DIR "/bench/scenes")) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    const Scene first = load_scene_file(entry.path().string());
    const json written = scene_to_json(first);
    const Scene second = scene_from_json(written, "summary.json");
    const json rewritten = scene_to_json(second);
    EXPECT_EQ(written, rewritten);
    EXPECT_EQ(written.dump(), rewritten.dump());  // number forms too (2 is not 2.0)
    expect_same_scene(first, second);
    const json given = json::parse(std::ifstream(entry.path()), nullptr, true, true);
    expect_contains(written, given, "");
    ++count;
  }
  EXPECT_GE(count, 10);
}

}  // namespace
}  // namespace chainmail

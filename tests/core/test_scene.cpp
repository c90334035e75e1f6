#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/scene.hpp"
#include "core/weave.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

json minimal_scene() {
  return json{
      {"name", "t"}, {"weave", {{"type", "4in1"}, {"rows", 4}, {"cols", 5}}}, {"duration", 0.1}};
}

// the message of the SceneError the document raises ("" when it loads)
std::string error_of(const json& document) {
  try {
    scene_from_json(document, "scene.json");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneLoad, MinimalSceneGetsDefaults) {
  const Scene scene = scene_from_json(minimal_scene(), "scene.json");
  EXPECT_EQ(scene.name, "t");
  EXPECT_DOUBLE_EQ(scene.ring.wire_diameter(), 0.0016);
  EXPECT_DOUBLE_EQ(scene.ring.inner_diameter(), 0.008);
  EXPECT_TRUE(scene.self_contact);
  EXPECT_EQ(scene.resolved["ring"]["density"], 7850.0);  // defaults written back
  EXPECT_EQ(scene.resolved["weave"]["plane"], "xz");
}

TEST(SceneLoad, ResolvedSceneReloadsToTheSameScene) {
  json doc = minimal_scene();
  doc["colliders"] = json::array({{{"type", "plane"}}});
  const Scene first = scene_from_json(doc, "scene.json");
  const Scene second = scene_from_json(first.resolved, "summary.json");
  EXPECT_EQ(first.resolved, second.resolved);
  EXPECT_TRUE(second.camera.automatic);
}

TEST(SceneLoad, UnknownKeyNamesKeyAndFile) {
  json doc = minimal_scene();
  doc["ring"] = {{"wire_diamter", 0.001}};
  const std::string error = error_of(doc);
  EXPECT_NE(error.find("scene.json"), std::string::npos) << error;
  EXPECT_NE(error.find("'ring.wire_diamter'"), std::string::npos) << error;
  EXPECT_NE(error.find("unknown key"), std::string::npos) << error;
}

TEST(SceneLoad, WrongTypeNamesKey) {
  json doc = minimal_scene();
  doc["duration"] = "long";
  EXPECT_NE(error_of(doc).find("'duration': must be a number"), std::string::npos);
  doc = minimal_scene();
  doc["weave"]["rows"] = 2.5;
  EXPECT_NE(error_of(doc).find("'weave.rows': must be an integer"), std::string::npos);
  doc = minimal_scene();
  doc["gravity"] = {0, -9.81};
  EXPECT_NE(error_of(doc).find("'gravity': must be an array of 3 numbers"), std::string::npos);
}

TEST(SceneLoad, MissingRequiredKey) {
  json doc = minimal_scene();
  doc.erase("weave");
  EXPECT_NE(error_of(doc).find("'weave': missing"), std::string::npos);
  doc = minimal_scene();
  doc["colliders"] = json::array({{{"type", "sphere"}, {"radius", 0.1}}});
  EXPECT_NE(error_of(doc).find("'colliders[0].center': missing"), std::string::npos);
}

TEST(SceneLoad, NonFiniteAndOutOfRange) {
  json doc = minimal_scene();
  doc["duration"] = std::numeric_limits<double>::infinity();
  EXPECT_NE(error_of(doc).find("'duration': must be finite"), std::string::npos);
  doc = minimal_scene();
  doc["ring"] = {{"wire_diameter", -0.001}};
  EXPECT_NE(error_of(doc).find("'ring.wire_diameter': must be in"), std::string::npos);
  doc = minimal_scene();
  doc["colliders"] = json::array({{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 0.0}}});
  EXPECT_NE(error_of(doc).find("'colliders[0].radius'"), std::string::npos);
}

TEST(SceneLoad, AspectRatioTooSmallToInterlock) {
  // a >= c (no hole) and a hole too small for 4-in-1 are both refused, naming the ring key
  json doc = minimal_scene();
  doc["ring"] = {{"wire_diameter", 0.002}, {"inner_diameter", 0.004}};  // AR 2 < 3.5
  const std::string error = error_of(doc);
  EXPECT_NE(error.find("'ring.inner_diameter'"), std::string::npos) << error;
  EXPECT_NE(error.find("too small"), std::string::npos) << error;
  doc["ring"] = {{"wire_diameter", 0.002}, {"inner_diameter", 0.0}};  // a >= c
  EXPECT_NE(error_of(doc).find("'ring.inner_diameter'"), std::string::npos);
  // the same rings are fine as a chain, which interlocks from AR 2
  doc["ring"] = {{"wire_diameter", 0.002}, {"inner_diameter", 0.005}};
  doc["weave"] = {{"type", "chain"}, {"cols", 5}};
  EXPECT_EQ(error_of(doc), "");
}

TEST(SceneLoad, PinsMustNameExistingRings) {
  json doc = minimal_scene();
  doc["pins"] = json::array({{{"ring", {3, 4}}}, {{"ring", {4, 0}}}});
  const std::string error = error_of(doc);
  EXPECT_NE(error.find("'pins[1].ring'"), std::string::npos) << error;
  EXPECT_NE(error.find("does not exist"), std::string::npos) << error;
  doc["pins"] = json::array({{{"corner", "middle"}}});
  EXPECT_NE(error_of(doc).find("'pins[0].corner'"), std::string::npos);
  doc["pins"] = json::array({{{"edge", "top"}, {"corner", "top_left"}}});
  EXPECT_NE(error_of(doc).find("exactly one"), std::string::npos);
}

TEST(SceneLoad, PinByRingIndexIsRowMajor) {
  json doc = minimal_scene();  // 4 rows of 5
  doc["pins"] = json::array({{{"ring", 17}}});
  const Scene scene = scene_from_json(doc, "scene.json");
  ASSERT_EQ(scene.pins.size(), 1u);
  EXPECT_EQ(scene.pins[0].row, 3);
  EXPECT_EQ(scene.pins[0].col, 2);
  EXPECT_EQ(scene.resolved["pins"][0]["ring"], json({3, 2}));
  doc["pins"] = json::array({{{"ring", 20}}});
  const std::string error = error_of(doc);
  EXPECT_NE(error.find("'pins[0].ring'"), std::string::npos) << error;
  EXPECT_NE(error.find("[0, 19]"), std::string::npos) << error;
}

TEST(SceneLoad, JsonSyntaxErrorHasLineAndColumn) {
  const auto path = std::filesystem::temp_directory_path() / "chainmail_bad_syntax.json";
  {
    std::ofstream out(path);
    out << "{\n  \"name\": \"x\",\n  \"duration\": 1.0,,\n}\n";
  }
  try {
    load_scene_file(path.string());
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    const std::string error = e.what();
    EXPECT_NE(error.find("syntax error"), std::string::npos) << error;
    EXPECT_NE(error.find("line 3"), std::string::npos) << error;
    EXPECT_NE(error.find("column"), std::string::npos) << error;
  }
  std::filesystem::remove(path);
}

TEST(SceneLoad, MissingFileIsClear) {
  EXPECT_THROW(load_scene_file("/nonexistent/scene.json"), SceneError);
}

TEST(SceneOverride, DottedPathsCreateAndReplace) {
  json doc = minimal_scene();
  apply_override(doc, "weave.rows=7", "f");
  apply_override(doc, "backends.bullet.dt=0.0005", "f");
  apply_override(doc, "gravity=[0,-1,0]", "f");
  apply_override(doc, "description=hello world", "f");
  EXPECT_EQ(doc["weave"]["rows"], 7);
  EXPECT_DOUBLE_EQ(doc["backends"]["bullet"]["dt"].get<double>(), 0.0005);
  EXPECT_EQ(doc["gravity"][1], -1);
  EXPECT_EQ(doc["description"], "hello world");
  doc["colliders"] = json::array({{{"type", "plane"}}});
  apply_override(doc, "colliders.0.friction=0.9", "f");
  EXPECT_DOUBLE_EQ(doc["colliders"][0]["friction"].get<double>(), 0.9);
}

TEST(SceneOverride, ValidatedLikeTheFile) {
  json doc = minimal_scene();
  apply_override(doc, "weave.rows=-3", "f");
  EXPECT_NE(error_of(doc).find("'weave.rows'"), std::string::npos);
  doc = minimal_scene();
  apply_override(doc, "weave.colour=red", "f");
  EXPECT_NE(error_of(doc).find("'weave.colour': unknown key"), std::string::npos);
  EXPECT_THROW(apply_override(doc, "no_equals_sign", "f"), SceneError);
  doc["colliders"] = json::array();
  EXPECT_THROW(apply_override(doc, "colliders.5.radius=1", "f"), SceneError);
}

TEST(SceneFiles, EveryBenchSceneLoads) {
  int count = 0;
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(CHAINMAIL_SOURCE_DIR "/bench/scenes")) {
    if (entry.path().extension() != ".json") continue;
    EXPECT_NO_THROW(load_scene_file(entry.path().string())) << entry.path();
    ++count;
  }
  EXPECT_GE(count, 5);
}

}  // namespace
}  // namespace chainmail

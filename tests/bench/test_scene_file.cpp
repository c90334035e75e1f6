#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <sys/stat.h>
#include <unistd.h>

#include "core/weave.hpp"
#include "scene_documents.hpp"
#include "scene_file/scene_file.hpp"
#include "scene_file/strict_json.hpp"
#include "test_temp.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

using test::minimal_scene;

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
  EXPECT_DOUBLE_EQ(scene.ring.density, 7850.0);
  EXPECT_EQ(scene.weave.plane, SheetPlane::xz);
  EXPECT_TRUE(scene.self_contact);
  EXPECT_TRUE(scene.camera.automatic);
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
  doc["pins"] = json::array({{{"ring", 20}}});
  const std::string error = error_of(doc);
  EXPECT_NE(error.find("'pins[0].ring'"), std::string::npos) << error;
  EXPECT_NE(error.find("[0, 19]"), std::string::npos) << error;
}

TEST(SceneLoad, JsonSyntaxErrorHasLineAndColumn) {
  const auto path = chainmail::test_temp_root() / "chainmail_bad_syntax.json";
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

// a scene file with this text in a per-process temp folder (other test runs share /tmp)
class SceneFile {
 public:
  explicit SceneFile(const std::string& text, const std::string& name = "scene.json") {
    std::filesystem::create_directories(dir());
    path_ = (dir() / name).string();
    std::ofstream(path_, std::ios::binary) << text;
  }
  ~SceneFile() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
    std::filesystem::remove(dir(), ignored);  // only when empty
  }
  const std::string& path() const { return path_; }
  static std::filesystem::path dir() {
    return chainmail::test_temp_root() / ("chainmail_test_scene_" + std::to_string(::getpid()));
  }

 private:
  std::string path_;
};

// the SceneError message loading this text (with these overrides) raises, "" when it loads
std::string file_error(const std::string& text, const std::vector<std::string>& overrides = {}) {
  const SceneFile file(text);
  try {
    load_scene_file(file.path(), overrides);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

std::string override_error(const std::string& assignment) {
  json doc = minimal_scene();
  doc["colliders"] = json::array({{{"type", "plane"}}, {{"type", "plane"}}});
  try {
    apply_override(doc, assignment, "scene.json");
    scene_from_json(doc, "scene.json");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

const std::string kMinimalText =
    R"({"name": "t", "weave": {"type": "4in1", "rows": 4, "cols": 5}, "duration": 0.1)";

std::string deep_arrays(int levels) {
  return std::string(levels, '[') + std::string(levels, ']');
}
std::string deep_objects(int levels) {
  std::string text;
  for (int k = 0; k < levels; ++k) text += R"({"a":)";
  return text + "1" + std::string(levels, '}');
}

// old code: the object case overflowed the stack (copying backends), the array case loaded
TEST(SceneStrictJson, DeepNestingIsRefusedWithoutRecursion) {
  constexpr int kLevels = 100000;
  for (const std::string& deep : {deep_arrays(kLevels), deep_objects(kLevels)}) {
    std::string error = file_error(deep);
    EXPECT_NE(error.find("nested deeper than 64 levels"), std::string::npos) << error;
    EXPECT_NE(error.find("scene.json"), std::string::npos) << error;
    error = file_error(kMinimalText + R"(, "backends": {"x": )" + deep + "}}");
    EXPECT_NE(error.find("key 'backends.x"), std::string::npos) << error.substr(0, 200);
    EXPECT_NE(error.find("nested deeper than 64 levels"), std::string::npos) << error;
    error = file_error(kMinimalText + "}", {"backends.x=" + deep});
    EXPECT_NE(error.find("--set key 'backends.x"), std::string::npos) << error.substr(0, 200);
    EXPECT_NE(error.find("nested deeper than 64 levels"), std::string::npos) << error;
  }
  // unterminated: refused for the depth before the end of input is reached
  EXPECT_NE(file_error(std::string(kLevels, '[')).find("nested deeper"), std::string::npos);
  // a --set path is nesting too
  std::string path = "backends";
  for (int k = 0; k < 100; ++k) path += ".a";
  EXPECT_NE(file_error(kMinimalText + "}", {path + "=1"}).find("nested deeper"), std::string::npos);
}

TEST(SceneStrictJson, NestingUpToTheLimitLoads) {
  // 64 levels in all: the top-level object, backends, then 62 arrays
  const std::string text = kMinimalText + R"(, "backends": {"x": )" + deep_arrays(62) + "}}";
  const std::string error = file_error(text);
  EXPECT_EQ(error.find("nested"), std::string::npos) << error;
  EXPECT_NE(file_error(kMinimalText + R"(, "backends": {"x": )" + deep_arrays(63) + "}}")
                .find("key 'backends.x"),
            std::string::npos);
}

TEST(SceneStrictJson, ParseJsonStrictLimitsAndComments) {
  const json doc =
      parse_json_strict("// a comment\n{\"x\": " + deep_arrays(kMaxJsonDepth - 1) + "}", "s.json");
  EXPECT_TRUE(doc["x"].is_array());
  try {
    parse_json_strict(deep_arrays(kMaxJsonDepth + 1), "s.json");
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("s.json: key '", 0), 0u) << e.what();
  }
  EXPECT_THROW(parse_json_strict("{\"a\": 1, \"a\": 1}", "s.json"), SceneError);
  EXPECT_THROW(parse_json_strict("[1e400]", "s.json"), SceneError);
  EXPECT_THROW(parse_json_strict("{", "s.json"), SceneError);
  EXPECT_THROW(parse_json_strict("\"\xff\"", "s.json"), SceneError);
  // a document built in code skips the parser: scene_from_json checks its depth without recursion
  json deep = json::array();
  for (int k = 0; k < 100000; ++k) deep = json::array({std::move(deep)});
  json scene = minimal_scene();
  scene["backends"] = {{"x", std::move(deep)}};
  EXPECT_NE(error_of(scene).find("nested deeper than 64 levels"), std::string::npos);
}

// old code: duplicates silently kept the last value
TEST(SceneStrictJson, DuplicateKeysAreRefused) {
  std::string error =
      file_error(R"({"name": "t", "weave": {"type": "4in1", "rows": 4, "rows": 5, "cols": 5},
                    "duration": 0.1})");
  EXPECT_NE(error.find("scene.json: key 'weave.rows': duplicate key"), std::string::npos) << error;
  error = file_error(kMinimalText + R"(, "duration": 0.2})");
  EXPECT_NE(error.find("key 'duration': duplicate key"), std::string::npos) << error;
  error = file_error(kMinimalText + R"(, "pins": [{"edge": "top"}, {"ring": 1, "ring": 2}]})");
  EXPECT_NE(error.find("key 'pins[1].ring': duplicate key"), std::string::npos) << error;
  // the same key in two objects is fine
  EXPECT_EQ(file_error(kMinimalText + R"(, "pins": [{"ring": 1}, {"ring": 2}]})"), "");
}

// old code: nlohmann's out_of_range escaped (exit 3), and a --set value became a string
TEST(SceneStrictJson, NumbersOutOfDoubleRangeNameTheKey) {
  std::string error = file_error(R"({"name": "t", "duration": 1e400})");
  EXPECT_NE(error.find("scene.json: key 'duration': number out of range: 1e400"), std::string::npos)
      << error;
  error = file_error(R"({"name": "t", "gravity": [0, -1e400, 0]})");
  EXPECT_NE(error.find("key 'gravity[1]': number out of range: -1e400"), std::string::npos)
      << error;
  const std::string huge(400, '9');
  error = file_error(R"({"name": "t", "weave": {"rows": )" + huge + "}}");
  EXPECT_NE(error.find("key 'weave.rows': number out of range: 9999"), std::string::npos) << error;
  EXPECT_LT(error.size(), 200u) << error;  // the number is shortened
  error = file_error(kMinimalText + "}", {"duration=1e400"});
  EXPECT_NE(error.find("--set key 'duration': number out of range: 1e400"), std::string::npos)
      << error;
  error = file_error(kMinimalText + "}", {"gravity=[0,1e999,0]"});
  EXPECT_NE(error.find("--set key 'gravity[1]': number out of range"), std::string::npos) << error;
  // hundreds of digits within double range: a number, but not an integer
  error = file_error(R"({"name": "t", "weave": {"type": "4in1", "rows": )" + std::string(300, '9') +
                     R"(, "cols": 5}, "duration": 0.1})");
  EXPECT_NE(error.find("key 'weave.rows': must be an integer"), std::string::npos) << error;
}

// old code: get<int>() wrapped 2^32 to 0 and the pin was accepted; 2^63 was shown negative
TEST(SceneLoad, HugeIntegersAreRangeCheckedAsWritten) {
  json doc = minimal_scene();
  doc["pins"] = json::array({{{"ring", {4294967296LL, 0}}}});
  std::string error = error_of(doc);
  EXPECT_NE(error.find("'pins[0].ring'"), std::string::npos) << error;
  EXPECT_NE(error.find("4294967296"), std::string::npos) << error;
  doc["pins"] = json::array({{{"ring", {0, -4294967296LL}}}});
  EXPECT_NE(error_of(doc).find("-4294967296"), std::string::npos);
  doc = minimal_scene();
  doc["loads"] = json::array({{{"ring", {0, 4294967297LL}}, {"mass_factor", 2.0}}});
  error = error_of(doc);
  EXPECT_NE(error.find("'loads[0].ring'"), std::string::npos) << error;
  EXPECT_NE(error.find("4294967297"), std::string::npos) << error;
  const std::string two63 = "9223372036854775808";
  error = file_error(R"({"name": "t", "weave": {"type": "4in1", "rows": )" + two63 +
                     R"(, "cols": 5}, "duration": 0.1})");
  EXPECT_NE(error.find("'weave.rows': must be in [1, 4096], got " + two63), std::string::npos)
      << error;
  error = file_error(kMinimalText + R"(, "pins": [{"ring": 18446744073709551615}]})");
  EXPECT_NE(error.find("got 18446744073709551615"), std::string::npos) << error;
  error = file_error(kMinimalText + R"(, "pins": [{"ring": [)" + two63 + ", 0]}]}");
  EXPECT_NE(error.find("row " + two63), std::string::npos) << error;
}

// old code: a grid spacing of 1e-300 (and rings of 1e-300 m) loaded and ran into inf
TEST(SceneLoad, LengthsAndDensityTooSmallForFiniteNumbersAreRefused) {
  json doc = minimal_scene();
  doc["weave"] = {{"type", "grid"}, {"rows", 4}, {"cols", 5}, {"spacing", 1e-300}};
  EXPECT_NE(error_of(doc).find("'weave.spacing': must be in [1e-06, 100], got 1e-300"),
            std::string::npos)
      << error_of(doc);
  const std::vector<std::pair<std::string, json>> cases = {
      {"wire_diameter", 1e-300}, {"inner_diameter", 1e-300}, {"density", 1e-300}};
  for (const auto& [key, value] : cases) {
    doc = minimal_scene();
    doc["ring"] = {{key, value}};
    EXPECT_NE(error_of(doc).find("'ring." + key + "': must be in"), std::string::npos) << key;
  }
  doc = minimal_scene();
  doc["colliders"] = json::array({{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1e-300}}});
  EXPECT_NE(error_of(doc).find("'colliders[0].radius': must be in"), std::string::npos);
  doc = minimal_scene();
  doc["support"] = {{"center", {0, 0, 0}}, {"radius", 1e-300}};
  EXPECT_NE(error_of(doc).find("'support.radius': must be in"), std::string::npos);
}

TEST(SceneLoad, ExtremeAcceptedRingsHaveFiniteMassAndLayout) {
  // the smallest and the largest rings the loader accepts, densest and lightest
  for (const json& ring :
       {json{{"wire_diameter", 1e-6}, {"inner_diameter", 4e-6}, {"density", 1.0}},
        json{{"wire_diameter", 1.0}, {"inner_diameter", 10.0}, {"density", 1e5}}}) {
    json doc = minimal_scene();
    doc["ring"] = ring;
    const Scene scene = scene_from_json(doc, "scene.json");
    EXPECT_TRUE(std::isfinite(scene.ring.mass()) && scene.ring.mass() > 0.0) << ring;
    EXPECT_TRUE(scene.ring.inertia().allFinite() && scene.ring.inertia().minCoeff() > 0.0) << ring;
    EXPECT_TRUE(make_weave(scene.weave, scene.ring).rest_position.allFinite()) << ring;
  }
  json doc = minimal_scene();
  doc["weave"] = {{"type", "grid"}, {"rows", 4}, {"cols", 5}, {"spacing", 1e-6}};
  const Scene grid = scene_from_json(doc, "scene.json");
  const Weave weave = make_weave(grid.weave, grid.ring);
  EXPECT_GT((weave.rest_position.col(1) - weave.rest_position.col(0)).norm(), 0.0);
}

// old code: a FIFO hung in open(), a directory read as an empty document ("syntax error")
TEST(SceneFiles, PathsThatAreNotSceneFilesAreRefused) {
  const auto dir = SceneFile::dir() / "paths";
  std::filesystem::create_directories(dir);
  const std::string fifo = (dir / "fifo.json").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto error_at = [](const std::string& path) -> std::string {
    try {
      load_scene_file(path);
    } catch (const SceneError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(error_at(fifo), fifo + ": is not a regular file (a FIFO)");
  EXPECT_EQ(error_at(dir.string()), dir.string() + ": is a directory, not a scene file");
  EXPECT_EQ(error_at("."), ".: is a directory, not a scene file");
  const std::string missing = (dir / "missing.json").string();
  EXPECT_EQ(error_at(missing), missing + ": cannot open the scene file: No such file or directory");
  EXPECT_EQ(error_at(""), "scene file: the path is empty");
  std::string error = error_at("/proc/self/mem");
  EXPECT_EQ(error.rfind("/proc/self/mem: cannot ", 0), 0u) << error;
  EXPECT_EQ(error_at("/dev/null"), "/dev/null: is not a regular file (a character device)");
  const std::string large = (dir / "large.json").string();
  std::ofstream(large) << "{}";
  std::filesystem::resize_file(large, (16u << 20) + 1);  // sparse: quick to make
  EXPECT_EQ(error_at(large), large + ": is larger than the 16 MiB limit for scene files");
  if (::geteuid() != 0) {  // root reads anything
    const std::string locked = (dir / "locked.json").string();
    std::ofstream(locked) << "{}";
    std::filesystem::permissions(locked, std::filesystem::perms::none);
    EXPECT_EQ(error_at(locked), locked + ": cannot open the scene file: Permission denied");
  }
  std::filesystem::remove_all(dir);
  std::error_code ignored;
  std::filesystem::remove(SceneFile::dir(), ignored);  // only when empty
}

// old code: said "weave.spacing: must be in [1, 1], got 1" (the default spacing range was empty)
TEST(SceneLoad, ChainAspectRatioJustTooSmallSaysSo) {
  json doc = minimal_scene();
  doc["weave"] = {{"type", "chain"}, {"cols", 5}};
  for (double inner : {0.0031999999, 0.00319999, 0.0031}) {
    doc["ring"] = {{"wire_diameter", 0.0016}, {"inner_diameter", inner}};
    const std::string error = error_of(doc);
    EXPECT_NE(error.find("key 'ring.inner_diameter': aspect ratio ID/WD = 1.9"), std::string::npos)
        << error;
    EXPECT_NE(error.find("chain weave to interlock (needs ID/WD >= 2, so inner_diameter >= 0.0032 "
                         "for this wire_diameter)"),
              std::string::npos)
        << error;
  }
  doc["ring"] = {{"wire_diameter", 0.0016}, {"inner_diameter", 0.0032}};
  EXPECT_EQ(error_of(doc), "");  // exactly AR 2 loads, spacing 1
  doc["weave"]["rows"] = 2;
  const std::string error = error_of(doc);
  EXPECT_NE(error.find("key 'weave.rows': a chain has one row"), std::string::npos) << error;
}

// old code: "a.b.=1" set a.b (getline dropped the trailing empty element), "colliders.1x" was
// index 1, and a value that is not UTF-8 went into the scene as a string
TEST(SceneOverride, MalformedKeysAreRefusedNamingTheKey) {
  EXPECT_EQ(override_error("weave.rows.=1"),
            "scene.json: --set key 'weave.rows.': empty path element (no leading, trailing or "
            "double dots)");
  EXPECT_EQ(override_error("weave..rows=1"),
            "scene.json: --set key 'weave..rows': empty path element (no leading, trailing or "
            "double dots)");
  EXPECT_EQ(override_error(".weave=1"),
            "scene.json: --set key '.weave': empty path element (no leading, trailing or double "
            "dots)");
  EXPECT_EQ(override_error("=1"), "scene.json: --set '=1': empty key (expected KEY=VALUE)");
  EXPECT_EQ(override_error("."), "scene.json: --set '.': expected KEY=VALUE");
  EXPECT_EQ(override_error("colliders.1x.friction=0.5"),
            "scene.json: --set key 'colliders.1x': expected an array index");
  EXPECT_EQ(override_error("colliders.-1.friction=0.5"),
            "scene.json: --set key 'colliders.-1': expected an array index");
  EXPECT_EQ(override_error("description=\xff\xfe"),
            "scene.json: --set key 'description': value is not valid UTF-8");
  EXPECT_EQ(override_error("colliders.1.friction=0.5"), "");
}

// old code: the raw key went into the message, breaking the one-line error
TEST(SceneLoad, MessagesStayOnOneLine) {
  json doc = minimal_scene();
  doc["we\nird"] = 1;
  EXPECT_EQ(error_of(doc), "scene.json: key 'we\\x0aird': unknown key");
  doc = minimal_scene();
  doc[std::string(500, 'k')] = 1;
  EXPECT_LT(error_of(doc).size(), 150u);
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

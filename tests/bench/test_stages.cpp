// What a scene leaves out never runs: stages and metrics in summary.json, in every backend.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "bench/harness/commands/commands.hpp"
#include "test_temp.hpp"

namespace chainmail {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// the stages each backend reports in summary.json
json stages_in_summary(const json& doc, const std::string& name) {
  const fs::path out = chainmail::test_temp_root() / ("chainmail_test_stages_" + name);
  fs::remove_all(out);
  fs::create_directories(out);
  const fs::path scene = out / "scene.json";
  std::ofstream(scene) << doc.dump();
  RunCommand run;
  run.scene_file = scene.string();
  run.backends = {"all"};
  run.out_dir = (out / "run").string();
  run.progress = false;
  run.cache_dir = (out / "cache").string();
  run_command(run);
  std::ifstream in(out / "run" / "summary.json");
  const json summary = json::parse(in);
  fs::remove_all(out);
  return summary.at("backends");
}

TEST(Stages, WhatASceneLeavesOutNeverRuns) {
  // no colliders -> no collision stage; no self-contact -> no spatial hash; no support -> no
  // drape coefficient: in every backend, read back from summary.json
  json doc = {{"name", "bare"},
              {"weave", {{"type", "4in1"}, {"rows", 4}, {"cols", 4}, {"plane", "xy"}}},
              {"pins", json::array({{{"edge", "top"}}})},
              {"features", {{"self_contact", false}}},
              {"duration", 0.02},
              {"sample_interval", 0.01},
              {"reference", "plausible"}};
  const json bare = stages_in_summary(doc, "bare");
  ASSERT_GE(bare.size(), 2u);
  for (const auto& [name, backend] : bare.items()) {
    SCOPED_TRACE(name);
    EXPECT_FALSE(backend["stages"].contains("colliders"));
    EXPECT_FALSE(backend["stages"].contains("self_contact"));
    EXPECT_FALSE(backend["stages"].empty());  // the model's own phases did run
    EXPECT_FALSE(backend["final"].contains("drape_coefficient"));
  }

  // the same scene with a floor just below, self-contact and a support: stages and metric appear
  doc["name"] = "full";
  doc["features"]["self_contact"] = true;
  doc["colliders"] = json::array({{{"type", "plane"}, {"point", {0, -0.02, 0}}}});
  doc["support"] = {{"center", {0, -0.02, 0}}, {"radius", 0.01}};
  const json full = stages_in_summary(doc, "full");
  ASSERT_EQ(full.size(), bare.size());
  for (const auto& [name, backend] : full.items()) {
    SCOPED_TRACE(name);
    EXPECT_GT(backend["stages"]["colliders"]["calls"].get<long long>(), 0);
    EXPECT_GT(backend["stages"]["self_contact"]["calls"].get<long long>(), 0);
    EXPECT_TRUE(backend["final"].contains("drape_coefficient"));
  }
}

}  // namespace
}  // namespace chainmail

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "bench/harness/commands.hpp"
#include "bench/harness/run.hpp"
#include "bench/harness/suites.hpp"

namespace chainmail {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

int count_lines(const fs::path& path) {
  std::ifstream in(path);
  int lines = 0;
  for (std::string line; std::getline(in, line);) lines += !line.empty();
  return lines;
}

std::string chainmail_binary() {
  return CHAINMAIL_BINARY_DIR "/bench/chainmail";
}

// the stages each backend reports in summary.json
json stages_in_summary(const json& doc, const std::string& name) {
  const fs::path out = fs::temp_directory_path() / ("chainmail_test_stages_" + name);
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

TEST(Catenary, ZeroOnTheCatenaryOneForAStraightChain) {
  const Scene scene = load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/chain_catenary.json");
  const Weave weave = make_weave(scene.weave, scene.ring);
  RingFrame frame;
  frame.resize(weave.size());
  frame.position = weave.rest_position;
  // the straight rest chain has no sag: error 1 (100 %)
  ASSERT_TRUE(catenary_error(scene, weave, frame).has_value());
  EXPECT_NEAR(*catenary_error(scene, weave, frame), 1.0, 1e-12);
  // rings lowered onto the catenary of the chain's length (n - 1) * 2(c - a): error 0
  const int n = weave.size();
  const double span = (weave.rest_position.col(n - 1) - weave.rest_position.col(0)).norm();
  const double length = (n - 1) * scene.ring.max_link_distance();
  double low = 1e-6, high = 1e3;  // m; 2A sinh(span / 2A) falls as A grows
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (low + high);
    (2.0 * mid * std::sinh(span / (2.0 * mid)) > length ? low : high) = mid;
  }
  const double A = 0.5 * (low + high);
  for (int i = 0; i < n; ++i) {
    const double x = (weave.rest_position.col(i) - weave.rest_position.col(0)).norm() - 0.5 * span;
    frame.position(1, i) -= A * (std::cosh(0.5 * span / A) - std::cosh(x / A));
  }
  EXPECT_NEAR(*catenary_error(scene, weave, frame), 0.0, 1e-3);  // rings sample the curve
  // a sheet is not a chain: no catenary error
  const Scene curtain = load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json");
  const Weave sheet = make_weave(curtain.weave, curtain.ring);
  RingFrame flat;
  flat.position = sheet.rest_position;
  EXPECT_FALSE(catenary_error(curtain, sheet, flat).has_value());
}

TEST(Sweep, OneRowPerPointAndThePlot) {
  const fs::path out = fs::temp_directory_path() / "chainmail_test_sweep";
  fs::remove_all(out);
  SweepCommand sweep;
  sweep.scene_file = CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json";
  sweep.overrides = {"weave.rows=4", "weave.cols=4", "duration=0.04", "reference=plausible"};
  sweep.vary = {"backends.{backend}.dt=0.004,0.002", "backends.{backend}.iterations=2,8"};
  sweep.backends = {"plausible"};
  sweep.out_dir = out.string();
  sweep.jobs = 2;
  sweep.executable = chainmail_binary();
  sweep.progress = false;
  sweep.cache_dir = (out.string() + "_cache");  // beside the output: inside it is not ours
  ASSERT_EQ(sweep_command(sweep), kExitOk);
  EXPECT_EQ(count_lines(out / "sweep.csv"), 1 + 4);  // header + 2 x 2 points
  std::ifstream csv(out / "sweep.csv");
  std::string header, row;
  std::getline(csv, header);
  EXPECT_NE(header.find("wall_per_sim_s"), std::string::npos);
  while (std::getline(csv, row)) EXPECT_NE(row.find(",true,stable"), std::string::npos) << row;
  if (!plotting_python().empty()) {
    EXPECT_TRUE(fs::exists(out / "sweep.png"));
    EXPECT_GT(fs::file_size(out / "sweep.png"), 1000u);
  }
  fs::remove_all(out);
  fs::remove_all(out.string() + "_cache");
}

TEST(Sweep, PrintJobsListsEveryPoint) {
  SweepCommand sweep;
  sweep.scene_file = CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json";
  sweep.vary = {"backends.{backend}.dt=0.004,0.002,0.001"};
  sweep.backends = {"plausible"};
  sweep.print_jobs = true;
  testing::internal::CaptureStdout();
  ASSERT_EQ(sweep_command(sweep), kExitOk);
  const std::string printed = testing::internal::GetCapturedStdout();
  int lines = 0;
  for (char ch : printed) lines += ch == '\n';
  EXPECT_EQ(lines, 3);
  EXPECT_NE(printed.find("--set 'backends.plausible.dt=0.001'"), std::string::npos) << printed;
  // the reference (bullet) is not swept: it runs at its dt in the scene
  EXPECT_NE(printed.find("--set 'reference_dt=0.001'"), std::string::npos) << printed;
  // a sweep over the reference backend's dt measures every point against its finest
  sweep.backends = {"plausible", "bullet"};
  sweep.vary = {"backends.{backend}.dt=0.004,0.0005"};
  testing::internal::CaptureStdout();
  ASSERT_EQ(sweep_command(sweep), kExitOk);
  const std::string finest = testing::internal::GetCapturedStdout();
  int pinned = 0;
  for (size_t at = 0; (at = finest.find("--set 'reference_dt=0.0005'", at)) != std::string::npos;
       ++at) {
    ++pinned;
  }
  EXPECT_EQ(pinned, 4) << finest;
  // a bad knob value is bad input before anything runs
  sweep.vary = {"backends.{backend}.dt=-1"};
  EXPECT_THROW(sweep_command(sweep), SceneError);
}

TEST(Bench, QuickModeWritesEveryResultsFile) {
  const fs::path out = fs::temp_directory_path() / "chainmail_test_bench";
  fs::remove_all(out);
  BenchCommand bench;
  bench.out_dir = out.string();
  bench.quick = true;
  bench.backends = {"plausible", "massspring"};  // massspring brings the stiffness study
  bench.executable = chainmail_binary();
  bench.render = false;
  bench.progress = false;
  ASSERT_EQ(bench_command(bench), kExitOk);
  for (const char* file :
       {"README.md", "timing.md", "timing.csv", "metrics.md", "sweep/curtain/sweep.csv",
        "sweep/table_cloth/sweep.csv", "stability/stability.md", "stability/stability.csv",
        "curtain/summary.json", "table_cloth/metrics.csv", "chain_catenary/table.md",
        "chain_pile/summary.json", "sphere_drape/summary.json"}) {
    EXPECT_TRUE(fs::exists(out / file)) << file;
  }
  EXPECT_EQ(count_lines(out / "timing.csv"), 1 + 5 * 2);  // five scenes, two backends
  if (!plotting_python().empty()) {
    EXPECT_TRUE(fs::exists(out / "sweep/curtain/sweep.png"));
    EXPECT_TRUE(fs::exists(out / "sweep/table_cloth/sweep.png"));
  }
  // every stability case has a row, the stiffness study's included
  std::ifstream stability(out / "stability/stability.csv");
  const std::string table((std::istreambuf_iterator<char>(stability)),
                          std::istreambuf_iterator<char>());
  for (const char* row : {"heavy_weight,plausible", "corners_pushed,massspring",
                          "springs_ks_500,massspring", "springs_ks_500000,massspring"}) {
    EXPECT_NE(table.find(row), std::string::npos) << row;
  }
  fs::remove_all(out);
}

}  // namespace
}  // namespace chainmail

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "bench/harness/commands.hpp"
#include "bench/harness/output.hpp"
#include "bench/harness/run.hpp"

namespace chainmail {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

Scene small_curtain(double duration = 0.2) {
  return scene_from_json(
      json{{"name", "small_curtain"},
           {"weave", {{"type", "4in1"}, {"rows", 6}, {"cols", 6}, {"plane", "xy"}}},
           {"pins", json::array({{{"edge", "top"}}})},
           {"duration", duration},
           {"sample_interval", 0.05},
           {"reference", "plausible"},
           {"backends", {{"plausible", json::object()}}}},
      "test");
}

RunOptions quiet() {
  RunOptions options;
  options.progress = false;
  return options;
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("chainmail_test_" + name);
  fs::remove_all(dir);
  return dir;
}

TEST(Run, BackendsReceiveIdenticalRestLayouts) {
  const Scene scene = small_curtain();
  const Weave weave = make_weave(scene.weave, scene.ring);
  std::vector<RingFrame> first;
  std::vector<std::string> names;
  for (const BackendInfo& info : backend_registry()) {
    std::unique_ptr<Backend> backend;
    try {
      backend = info.create();
    } catch (const std::exception&) {
      continue;  // a backend not built into this binary
    }
    backend->reset(scene, weave, resolve_knobs(scene, info));
    RingFrame frame;
    backend->frame(frame);
    first.push_back(frame);
    names.push_back(info.name);
  }
  ASSERT_GE(first.size(), 1u);
  for (size_t k = 0; k < first.size(); ++k) {
    // rigid backends scale lengths internally: equal up to the round trip through that unit
    // (below a nanometre; a ring is millimetres)
    EXPECT_LT((first[k].position - weave.rest_position).cwiseAbs().maxCoeff(), 1e-9) << names[k];
    EXPECT_DOUBLE_EQ(first[k].t, 0.0);
  }
}

TEST(Run, EveryBackendStartsFreeRingsAtTheSceneInitialVelocity) {
  // one free ring thrown sideways without gravity: after 0.1 s it has moved v t in every backend
  // built into this binary
  const Scene scene =
      scene_from_json(json{{"name", "thrown"},
                           {"weave", {{"type", "4in1"}, {"rows", 1}, {"cols", 1}, {"plane", "xz"}}},
                           {"gravity", {0, 0, 0}},
                           {"initial_velocity", {0.5, 0, 0}},
                           {"duration", 0.1},
                           {"reference", "plausible"},
                           // undamped, so that v t is exact
                           {"backends",
                            {{"plausible", {{"damping", 0.0}}},
                             {"massspring", {{"damping_percent", 0.0}}},
                             {"bullet", {{"linear_damping", 0.0}}},
                             {"ode", {{"linear_damping", 0.0}}}}}},
                      "test");
  const Weave weave = make_weave(scene.weave, scene.ring);
  int checked = 0;
  for (const BackendInfo& info : backend_registry()) {
    SCOPED_TRACE(info.name);
    const Knobs knobs = resolve_knobs(scene, info);
    std::unique_ptr<Backend> backend = info.create();
    backend->reset(scene, weave, knobs);
    const long steps = std::lround(scene.duration / knobs.at("dt"));
    for (long k = 0; k < steps; ++k) backend->step(knobs.at("dt"));
    RingFrame frame;
    backend->frame(frame);
    EXPECT_NEAR(frame.position(0, 0) - weave.rest_position(0, 0), 0.05, 0.05 * 0.02);
    EXPECT_NEAR(frame.velocity(0, 0), 0.5, 0.5 * 0.02);
    ++checked;
  }
  EXPECT_GE(checked, 2);
}

TEST(Run, DrapeRmsOfARunAgainstItselfIsZero) {
  const SceneRun run = run_scene(small_curtain(), quiet());
  ASSERT_EQ(run.runs.size(), 1u);
  for (const Sample& s : run.runs[0].samples) {
    ASSERT_TRUE(s.metrics.drape_rms.has_value());
    EXPECT_EQ(*s.metrics.drape_rms, 0.0);
  }
  EXPECT_EQ(drape_rms(run.runs[0].final_frame, run.runs[0].final_frame), 0.0);
}

TEST(Run, SameSceneTwiceSameHash) {
  const SceneRun a = run_scene(small_curtain(), quiet());
  const SceneRun b = run_scene(small_curtain(), quiet());
  EXPECT_EQ(a.runs[0].hash, b.runs[0].hash);
  EXPECT_NE(a.runs[0].hash, 0u);
}

TEST(Run, InjectedInstabilityIsReportedNotCrashed) {
  // a time step far too large for the repulsion springs: the run must end with a verdict
  json doc = small_curtain(1.0).resolved;
  doc["weave"] = {{"type", "4in1"}, {"rows", 8}, {"cols", 8}, {"plane", "xz"}};
  doc["pins"] = json::array();
  doc["backends"] = {
      {"plausible", {{"dt", 0.05}, {"repulsion_stiffness", 1e6}, {"repulsion_fraction", 1.5}}}};
  const Scene scene = scene_from_json(doc, "test");
  const SceneRun run = run_scene(scene, quiet());
  ASSERT_EQ(run.runs.size(), 1u);
  EXPECT_FALSE(run.runs[0].stable);
  EXPECT_NE(run.runs[0].verdict, "stable");
  EXPECT_FALSE(run.all_stable());
}

TEST(Run, ContractFilesWritten) {
  const fs::path dir = fresh_dir("contract");
  SceneRun run = run_scene(small_curtain(), quiet());
  OutputOptions output;
  output.frames = true;
  write_run_folder(run, dir.string(), output);

  std::ifstream summary_file(dir / "summary.json");
  const json summary = json::parse(summary_file);
  const json& entry = summary["backends"]["plausible"];
  for (const char* key : {"dt", "steps", "wall_s", "ms_per_step", "realtime_factor", "stable",
                          "verdict", "hash", "final"}) {
    EXPECT_TRUE(entry.contains(key)) << key;
  }
  EXPECT_TRUE(summary["ring"].contains("wire_radius"));
  EXPECT_TRUE(entry["final"].contains("max_stretch"));
  EXPECT_FALSE(entry["final"].contains("drape_coefficient"));  // no support: absent, not zero

  std::ifstream csv(dir / "metrics.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("backend,t,max_stretch,", 0), 0u) << header;
  EXPECT_NE(header.find(",step_wall_ms"), std::string::npos);

  std::ifstream frame(dir / "frames/plausible/00000.csv");
  std::getline(frame, header);
  EXPECT_EQ(header, "ring,i,j,x,y,z,qw,qx,qy,qz");
  EXPECT_TRUE(fs::exists(dir / "table.md"));
  // nothing left behind from the staging folder
  for (const auto& e : fs::directory_iterator(dir.parent_path())) {
    EXPECT_EQ(e.path().filename().string().find("chainmail_test_contract.partial"),
              std::string::npos);
  }
}

TEST(Run, BadInputExitsTwoAndWritesNothing) {
  const fs::path dir = fresh_dir("bad_input");
  const fs::path scene_path = fs::temp_directory_path() / "chainmail_bad_scene.json";
  {
    std::ofstream out(scene_path);
    out << R"({"name": "bad", "weave": {"type": "4in1", "rows": 2, "cols": 2}, "duration": -1})";
  }
  RunCommand command;
  command.scene_file = scene_path.string();
  command.out_dir = dir.string();
  command.progress = false;
  EXPECT_THROW(run_command(command), SceneError);
  EXPECT_FALSE(fs::exists(dir));
  // a bad backend name and a bad knob are refused the same way
  command.scene_file = CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json";
  command.backends = {"nosuch"};
  EXPECT_THROW(run_command(command), SceneError);
  command.backends = {"plausible"};
  command.overrides = {"backends.plausible.iterations=0"};
  EXPECT_THROW(run_command(command), SceneError);
  EXPECT_FALSE(fs::exists(dir));
}

}  // namespace
}  // namespace chainmail

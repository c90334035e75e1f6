#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <limits>
#include <thread>

#include "backends/backend.hpp"
#include "bench/harness/commands/commands.hpp"
#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/common/version.hpp"
#include "bench/harness/output/frame_stream.hpp"
#include "bench/harness/output/number_format.hpp"
#include "bench/harness/output/output.hpp"
#include "bench/harness/run/run.hpp"
#include "bench/harness/suites/sweep.hpp"
#include "core/parallel.hpp"
#include "scene_file/scene_file.hpp"
#include "test_temp.hpp"

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
  const fs::path dir = chainmail::test_temp_root() / ("chainmail_test_" + name);
  fs::remove_all(dir);
  return dir;
}

// a backend the project has that this binary was built without ("" when every one is built)
std::string unbuilt_backend() {
  for (const auto& name : known_backend_names()) {
    if (!backend_built(name)) return name;
  }
  return "";
}

// rings that stay at their rest layout, but whose model reports a non-finite state from its
// third step on: the runner must end the run on that report alone
class FailingBackend final : public Backend {
 public:
  const char* name() const override { return "failing"; }
  void reset(const Scene&, const Weave& weave, const Knobs&) override { weave_ = weave; }
  StepStatus step(double dt) override {
    t_ += dt;
    return ++steps_ >= 3 ? StepStatus::non_finite : StepStatus::ok;
  }
  void frame(RingFrame& out) const override {
    out.resize(weave_.size());
    out.t = t_;
    out.position = weave_.rest_position;
    out.orientation = weave_.rest_orientation;
    out.velocity.setZero();
  }
  const StageProfile& profile() const override { return profile_; }

 private:
  Weave weave_;
  double t_ = 0.0;
  int steps_ = 0;
  StageProfile profile_;
};

BackendInfo failing_backend_info() {
  BackendInfo info;
  info.name = "failing";
  info.knobs = {{"dt", KnobSpec::Type::number, 0.01, 1e-5, 0.1, "time step, s", {}}};
  info.create = [] { return std::make_unique<FailingBackend>(); };
  return info;
}

TEST(Run, BackendsReceiveIdenticalRestLayouts) {
  const Scene scene = small_curtain();
  const Weave weave = make_weave(scene.weave, scene.ring);
  std::vector<RingFrame> first;
  std::vector<std::string> names;
  for (const BackendInfo& info : backend_registry()) {
    std::unique_ptr<Backend> backend = info.create();
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

TEST(Run, DrapeRmsAgainstItsOwnCachedRunIsZero) {
  // the first run fills the cache with the reference frames, the second reads them back from the
  // file (not from memory) and measures itself against them
  const fs::path dir = fresh_dir("drape_cache");
  RunOptions options = quiet();
  options.cache_dir = (dir / "cache").string();
  const SceneRun first = run_scene(small_curtain(), options);
  const std::string cached = reference_cache_path(small_curtain(), "plausible", options.cache_dir);
  ASSERT_TRUE(fs::exists(cached));
  std::vector<double> drape;
  const Scene scene = small_curtain();
  const Weave weave = make_weave(scene.weave, scene.ring);
  auto reader = FrameReader::open(cached, weave.size());
  ASSERT_TRUE(reader.has_value());
  EXPECT_EQ(reader->count(), 5u);  // 0.2 s sampled every 0.05 s
  RingFrame last;
  ASSERT_TRUE(reader->read(reader->count() - 1, last));
  EXPECT_EQ(drape_rms(first.runs[0].final_frame, last), 0.0);
  const SceneRun second = run_scene(small_curtain(), options);
  ASSERT_TRUE(second.runs[0].final_metrics().drape_rms.has_value());
  EXPECT_EQ(*second.runs[0].final_metrics().drape_rms, 0.0);
  fs::remove_all(dir);
}

TEST(Run, CorruptCacheFileIsAMissNeverAnAllocation) {
  const fs::path dir = fresh_dir("corrupt_cache");
  RunOptions options = quiet();
  options.cache_dir = (dir / "cache").string();
  const std::string path = reference_cache_path(small_curtain(), "plausible", options.cache_dir);
  fs::create_directories(dir / "cache");
  // a header that claims 2^40 rings, then a few bytes: the old format's reader allocated that
  {
    std::ofstream out(path, std::ios::binary);
    const long long header[3] = {1LL << 40, 7LL << 40, 0};
    out.write("CMFRM001", 8);
    out.write(reinterpret_cast<const char*>(header), sizeof header);
    out << "short";
  }
  EXPECT_FALSE(FrameReader::open(path, 36).has_value());
  const SceneRun run = run_scene(small_curtain(), options);
  ASSERT_TRUE(run.runs[0].final_metrics().drape_rms.has_value());
  EXPECT_TRUE(FrameReader::open(path, 36).has_value());  // replaced by a good one
  fs::remove_all(dir);
}

TEST(Run, SameSceneTwiceSameHash) {
  const SceneRun a = run_scene(small_curtain(), quiet());
  const SceneRun b = run_scene(small_curtain(), quiet());
  EXPECT_EQ(a.runs[0].hash, b.runs[0].hash);
  EXPECT_NE(a.runs[0].hash, 0u);
}

TEST(Run, ThreadCountChangesNeitherTheResultNorWhatIsRecorded) {
  // a 40 x 40 curtain with self-contact (large enough for every loop of the plausible step to
  // split): --threads 1 and 2 end on the same bits, and the summary records the count used
  const Scene scene = scene_from_json(
      json{{"name", "threads"},
           {"weave", {{"type", "4in1"}, {"rows", 40}, {"cols", 40}, {"plane", "xy"}}},
           {"pins", json::array({{{"edge", "top"}}})},
           {"features", {{"self_contact", true}}},
           {"duration", 0.1},
           {"sample_interval", 0.05},
           {"backends", {{"plausible", json::object()}}}},
      "test");
  RunOptions one = quiet(), two = quiet();
  one.reference = two.reference = kNoReference;
  one.threads = 1;
  two.threads = 2;
  const SceneRun a = run_scene(scene, one);
  const SceneRun b = run_scene(scene, two);
  ASSERT_EQ(a.runs.size(), 1u);
  EXPECT_EQ(a.runs[0].hash, b.runs[0].hash);
  EXPECT_EQ(summary_json(a)["build"]["threads"], 1);
  EXPECT_EQ(summary_json(b)["build"]["threads"], 2);
}

TEST(Run, SweepPointsShareTheHardwareThreads) {
  SweepCommand command;
  command.jobs = 1;
  EXPECT_EQ(sweep_threads(command), hardware_threads());
  command.jobs = 2 * hardware_threads();
  EXPECT_EQ(sweep_threads(command), 1);  // never fewer than one
  command.threads = 3;
  EXPECT_EQ(sweep_threads(command), 3);  // --threads wins
}

TEST(Run, InjectedInstabilityIsReportedNotCrashed) {
  // a time step far too large for the paper's explicit repulsion springs, with one sweep and no
  // Newton steps to hold the weave together. A range of 1.5 inner diameters puts
  // non-neighbours inside it at the rest layout, and 1e6 N/m over 0.05 s throws them at
  // kilometres per second in the first step: the first sample after it is still finite, so the
  // first check that fails is max_speed (before torn_links, which fails too)
  json doc = scene_to_json(small_curtain(1.0));
  doc["weave"] = {{"type", "4in1"}, {"rows", 8}, {"cols", 8}, {"plane", "xz"}};
  doc["pins"] = json::array();
  doc["backends"] = {{"plausible",
                      {{"dt", 0.05},
                       {"repulsion_spring", true},
                       {"newton_steps", 0},
                       {"iterations", 1},
                       {"repulsion_stiffness", 1e6},
                       {"repulsion_fraction", 1.5}}}};
  const Scene scene = scene_from_json(doc, "test");
  const SceneRun run = run_scene(scene, quiet());
  ASSERT_EQ(run.runs.size(), 1u);
  EXPECT_FALSE(run.runs[0].stable);
  EXPECT_EQ(run.runs[0].verdict, Verdict::max_speed) << to_string(run.runs[0].verdict);
  EXPECT_EQ(run.runs[0].steps, 1);  // the run ends at the sample that failed
  EXPECT_GT(run.runs[0].final_metrics().max_speed, scene.stability.max_speed);
  EXPECT_FALSE(run.all_stable());
}

TEST(Run, StepReportingNonFiniteEndsTheRunWithThatVerdict) {
  // dt 0.01 s, samples every 0.05 s: the report comes at step 3, between two samples
  const Scene scene = small_curtain();
  const Weave weave = make_weave(scene.weave, scene.ring);
  std::vector<double> sampled;
  const BackendRun run =
      run_backend(scene, weave, failing_backend_info(), quiet(),
                  [&](const RingFrame&, Sample& sample) { sampled.push_back(sample.t); });
  EXPECT_FALSE(run.stable);
  EXPECT_EQ(run.verdict, Verdict::non_finite) << to_string(run.verdict);
  EXPECT_EQ(run.steps, 3);
  // a sample of the state it reported, though its frame looks finite
  ASSERT_EQ(sampled.size(), 2u);
  EXPECT_NEAR(sampled[1], 0.03, 1e-12);
  EXPECT_EQ(run.final_metrics().non_finite, 0);
  EXPECT_FALSE(run.settled.has_value());  // decided only for runs that ended stable
}

TEST(Run, VerdictNamesReadBackAsTheirVerdicts) {
  for (Verdict verdict :
       {Verdict::stable, Verdict::non_finite, Verdict::max_speed, Verdict::torn_links,
        Verdict::energy_growth, Verdict::watchdog, Verdict::interrupted}) {
    const std::optional<Verdict> back = verdict_from_string(to_string(verdict));
    ASSERT_TRUE(back.has_value()) << to_string(verdict);
    EXPECT_EQ(*back, verdict) << to_string(verdict);
  }
  EXPECT_STREQ(to_string(Verdict::torn_links), "torn_links");  // as docs/metrics.md names it
  EXPECT_FALSE(verdict_from_string("error").has_value());      // a sweep point without a result
  EXPECT_FALSE(verdict_from_string("Stable").has_value());
}

TEST(Run, SceneBackendsNotBuiltAreSkipped) {
  // a scene that configures every backend the project has runs those built into this binary
  json doc = scene_to_json(small_curtain());
  for (const auto& name : known_backend_names()) doc["backends"][name] = json::object();
  const Scene scene = scene_from_json(doc, "test");
  EXPECT_EQ(select_backends(scene, {}), built_backend_names());
  EXPECT_EQ(select_backends(scene, {"all"}), built_backend_names());
  EXPECT_EQ(select_backends(scene, {"massspring", "plausible", "massspring"}),
            (std::vector<std::string>{"massspring", "plausible"}));
}

TEST(Run, NamingABackendNotBuiltIsAUsageError) {
  const std::string unbuilt = unbuilt_backend();
  if (unbuilt.empty()) GTEST_SKIP() << "every backend is built into this binary";
  try {
    select_backends(small_curtain(), {"plausible", unbuilt});
    FAIL() << "no error for " << unbuilt;
  } catch (const UsageError& e) {
    EXPECT_EQ(std::string(e.what()), "--backends: " + unbuilt +
                                         " is not built into this binary (built: " +
                                         join_names(built_backend_names()) + ")");
  }
  RunCommand command;
  command.scene_file = CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json";
  command.backends = {"plausible"};
  command.reference = unbuilt;
  command.out_dir = fresh_dir("unbuilt_reference_flag").string();
  EXPECT_THROW(run_command(command), UsageError);
  EXPECT_FALSE(fs::exists(command.out_dir));
}

TEST(Run, ReferenceNotBuiltRunsWithoutDrapeRms) {
  const std::string unbuilt = unbuilt_backend();
  if (unbuilt.empty()) GTEST_SKIP() << "every backend is built into this binary";
  json doc = scene_to_json(small_curtain());
  doc["reference"] = unbuilt;
  const Scene scene = scene_from_json(doc, "test");
  EXPECT_EQ(reference_backend(scene, quiet()), "");
  const SceneRun run = run_scene(scene, quiet());
  ASSERT_EQ(run.runs.size(), 1u);
  EXPECT_TRUE(run.all_stable());
  EXPECT_FALSE(run.runs[0].final_metrics().drape_rms.has_value());
  EXPECT_EQ(run.reference_note.value_or(""),
            "no reference run (" + unbuilt + " is not built into this binary): drape_rms absent");
}

TEST(Run, ContractFilesWritten) {
  const fs::path dir = fresh_dir("contract");
  RunOptions options = quiet();
  options.folder = dir.string();
  options.frame_csv = true;
  SceneRun run = run_scene(small_curtain(), options);
  write_run_folder(run, dir.string(), OutputOptions{});

  std::ifstream summary_file(dir / "summary.json");
  const json summary = json::parse(summary_file);
  const json& entry = summary["backends"]["plausible"];
  for (const char* key : {"dt", "steps", "wall_s", "ms_per_step", "realtime_factor", "stable",
                          "verdict", "hash", "final", "settled", "overstretched"}) {
    EXPECT_TRUE(entry.contains(key)) << key;
  }
  EXPECT_TRUE(summary["ring"].contains("wire_radius"));
  // what built it and where it ran
  const json& build = summary["build"];
  EXPECT_EQ(build["version"], chainmail_version());
  EXPECT_EQ(build["commit"], chainmail_commit());
  EXPECT_EQ(build["compiler"], chainmail_compiler());
  EXPECT_EQ(build["build_type"], chainmail_build_type());
  EXPECT_FALSE(build["build_type"].get<std::string>().empty());
  EXPECT_EQ(build["threads"], 1);  // every backend steps on one thread
  EXPECT_EQ(build["host_cores"], std::thread::hardware_concurrency());
  EXPECT_EQ(build.size(), 6u);
  for (const char* key : {"max_stretch", "penetration_max_linked", "penetration_mean_other"})
    EXPECT_TRUE(entry["final"].contains(key)) << key;
  EXPECT_FALSE(entry["final"].contains("drape_coefficient"));  // no support: absent, not zero

  std::ifstream csv(dir / "metrics.csv");
  std::string header, row;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("backend,t,max_stretch,", 0), 0u) << header;
  EXPECT_NE(header.find(",step_wall_ms"), std::string::npos);
  int rows = 0;
  while (std::getline(csv, row)) rows += row.rfind("plausible,", 0) == 0;
  EXPECT_EQ(rows, 5);  // every sample, streamed while it ran

  std::ifstream frame(dir / "frames/plausible/00000.csv");
  std::getline(frame, header);
  EXPECT_EQ(header, "ring,i,j,x,y,z,qw,qx,qy,qz");
  EXPECT_TRUE(fs::exists(dir / "frames/plausible/00004.csv"));
  EXPECT_TRUE(fs::exists(dir / "table.md"));
  EXPECT_FALSE(fs::exists(dir / ".streams"));  // working files are gone
  fs::remove_all(dir);
}

TEST(Run, NonFiniteValuesNeverReachAFile) {
  Sample sample;
  sample.t = 0.5;
  sample.metrics.max_stretch = std::numeric_limits<double>::quiet_NaN();
  sample.metrics.kinetic_energy = std::numeric_limits<double>::infinity();
  sample.metrics.max_speed = -std::numeric_limits<double>::infinity();
  const std::string row = metrics_row("plausible", sample);
  EXPECT_EQ(row.find("nan"), std::string::npos) << row;
  EXPECT_EQ(row.find("inf"), std::string::npos) << row;
  EXPECT_TRUE(json_number(std::numeric_limits<double>::infinity()).is_null());
  EXPECT_TRUE(json_number(std::nan("")).is_null());
  EXPECT_EQ(csv_number(-std::numeric_limits<double>::infinity()), "");
}

TEST(Run, SettledAgainstTheEnergyReleased) {
  // physics, not the code's idea of it: a ring in free fall has turned all the potential energy
  // it lost into kinetic energy (not settled); a ring lying on the ground keeps none (settled)
  json doc = scene_to_json(small_curtain(0.3));
  doc["weave"] = {{"type", "4in1"}, {"rows", 1}, {"cols", 1}, {"plane", "xz"}};
  doc["pins"] = json::array();
  const SceneRun falling = run_scene(scene_from_json(doc, "test"), quiet());
  ASSERT_TRUE(falling.runs[0].settled.has_value());
  EXPECT_FALSE(*falling.runs[0].settled);
  // resting on the plane y = 0: the 4-in-1 rest layout tilts the ring, so its torus reaches
  // a + c sqrt(1 - (axis . y)^2) below its centre (exact torus geometry)
  const Scene lone = scene_from_json(doc, "test");
  const Weave weave = make_weave(lone.weave, lone.ring);
  const Orientations& o = weave.rest_orientation;
  const Vec3 axis = Quat(o(0, 0), o(1, 0), o(2, 0), o(3, 0)) * Vec3::UnitY();
  const double reach =
      lone.ring.wire_radius + lone.ring.centre_radius * std::sqrt(1.0 - axis.y() * axis.y());
  doc["weave"]["center"] = {0, reach, 0};
  doc["colliders"] = json::array({{{"type", "plane"}, {"point", {0, 0, 0}}}});
  doc["duration"] = 1.0;
  const SceneRun resting = run_scene(scene_from_json(doc, "test"), quiet());
  ASSERT_TRUE(resting.runs[0].settled.has_value());
  EXPECT_TRUE(*resting.runs[0].settled);
}

TEST(Run, ResidualOfTheSolveIsReportedAgainstItsTolerance) {
  // the converged solve, reachable by knobs (one substep, Newton steps wherever the sweeps leave
  // more than the tolerance), ends every step within it; one sweep a step without Newton steps
  // cannot hang a curtain and says so in its residual
  json converged_doc = scene_to_json(small_curtain());
  converged_doc["backends"] = {{"plausible", {{"substeps", 1}, {"newton_level", 0.0}}}};
  const SceneRun converged = run_scene(scene_from_json(converged_doc, "test"), quiet());
  const ResidualStats& good = converged.runs[0].residual;
  EXPECT_EQ(good.steps, converged.runs[0].steps);
  EXPECT_GT(good.tolerance, 0.0);
  EXPECT_EQ(good.unconverged, 0);
  EXPECT_LE(good.last, good.tolerance);
  json doc = scene_to_json(small_curtain());
  doc["backends"] = {{"plausible", {{"iterations", 1}, {"substeps", 1}, {"newton_steps", 0}}}};
  const SceneRun capped = run_scene(scene_from_json(doc, "test"), quiet());
  const ResidualStats& bad = capped.runs[0].residual;
  EXPECT_GT(bad.unconverged, 0);
  EXPECT_GT(bad.max, bad.tolerance);
  EXPECT_GE(bad.max, bad.last);
}

TEST(Run, OverstretchedIsFlaggedApartFromStability) {
  // a sheet hitting a sphere at 10 m/s: the paper's model lets links stretch past the inner
  // diameter (impossible for real rings) without going unstable
  json doc = scene_to_json(small_curtain(0.2));
  doc["weave"] = {
      {"type", "4in1"}, {"rows", 6}, {"cols", 6}, {"plane", "xz"}, {"center", {0, 0.05, 0}}};
  doc["pins"] = json::array();
  doc["initial_velocity"] = {0, -10, 0};
  doc["colliders"] = json::array({{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 0.02}}});
  doc["stability"] = {{"max_speed", 40.0}};
  const SceneRun impact = run_scene(scene_from_json(doc, "test"), quiet());
  const BackendRun& run = impact.runs[0];
  ASSERT_TRUE(run.overstretched.has_value());
  EXPECT_EQ(*run.overstretched, run.peak_stretch > 1.0 + kOverstretchTolerance);
  EXPECT_GE(run.peak_stretch, run.final_metrics().max_stretch);
  // a curtain at rest layout is not
  const SceneRun curtain = run_scene(small_curtain(0.05), quiet());
  ASSERT_TRUE(curtain.runs[0].overstretched.has_value());
  EXPECT_FALSE(*curtain.runs[0].overstretched);
}

TEST(Run, BadInputExitsTwoAndWritesNothing) {
  const fs::path dir = fresh_dir("bad_input");
  const fs::path scene_path = chainmail::test_temp_root() / "chainmail_bad_scene.json";
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
  // a bad backend name (a usage error) and a bad knob (a scene error) are refused the same way
  command.scene_file = CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json";
  command.backends = {"nosuch"};
  EXPECT_THROW(run_command(command), UsageError);
  command.backends = {"plausible"};
  command.overrides = {"backends.plausible.iterations=0"};
  EXPECT_THROW(run_command(command), SceneError);
  EXPECT_FALSE(fs::exists(dir));
}

}  // namespace
}  // namespace chainmail

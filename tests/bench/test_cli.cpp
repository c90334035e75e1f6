// The chainmail command as a user meets it: exit statuses, one message naming the key, nothing
// written on bad input, and the files a good run leaves.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "backends/backend.hpp"
#include "bench/harness/common/version.hpp"
#include "scene_file/scene_file.hpp"
#include "test_temp.hpp"

namespace chainmail {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

struct Outcome {
  int status = -1;     // exit status
  std::string output;  // stdout and stderr together
};

// a shell line's exit status and output (stdout and stderr together)
Outcome capture(const std::string& line) {
  Outcome outcome;
  FILE* pipe = ::popen(line.c_str(), "r");
  if (!pipe) return outcome;
  char buffer[4096];
  for (size_t got; (got = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) {
    outcome.output.append(buffer, got);
  }
  const int raw = ::pclose(pipe);
  outcome.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return outcome;
}

Outcome chainmail(const std::string& arguments, const std::string& environment = "") {
  return capture(environment + " " + CHAINMAIL_BINARY_DIR "/bench/chainmail " + arguments +
                 " 2>&1");
}

// a bash line as given (for background jobs and signals)
Outcome chainmail_shell(const std::string& line) {
  return capture("bash -c '" + line + "' 2>&1");
}

int lines(const std::string& text) {
  int count = 0;
  for (char ch : text) count += ch == '\n';
  return count;
}

class Cli : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = chainmail::test_temp_root() /
           ("chainmail_test_cli_" +
            std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // a small scene file: a 4x4 curtain of the plausible model, with `change` merged in
  std::string scene(const json& change = json::object()) {
    json doc = {{"name", "cli"},
                {"weave", {{"type", "4in1"}, {"rows", 4}, {"cols", 4}, {"plane", "xy"}}},
                {"pins", json::array({{{"edge", "top"}}})},
                {"duration", 0.05},
                {"sample_interval", 0.01},
                {"reference", "plausible"},
                {"backends", {{"plausible", json::object()}}}};
    doc.merge_patch(change);
    const fs::path path = dir_ / "scene.json";
    std::ofstream(path) << doc.dump(2);
    return path.string();
  }
  std::string out() const { return (dir_ / "out").string(); }
  std::string cache() const { return " --cache " + (dir_ / "cache").string(); }

  fs::path dir_;
};

TEST_F(Cli, GoodRunExitsZeroAndWritesTheContractFiles) {
  const Outcome run = chainmail("run " + scene() + " --frames --quiet --out " + out() + cache());
  ASSERT_EQ(run.status, 0) << run.output;
  for (const char* file : {"summary.json", "metrics.csv", "table.md", "frames/plausible/00000.csv"})
    EXPECT_TRUE(fs::exists(fs::path(out()) / file)) << file;
}

TEST_F(Cli, UnknownSceneKeyExitsTwoNamingKeyAndFileAndWritesNothing) {
  const std::string file = scene({{"weave", {{"colums", 4}}}});
  const Outcome run = chainmail("run " + file + " --quiet --out " + out() + cache());
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(lines(run.output), 1) << run.output;
  EXPECT_NE(run.output.find("weave.colums"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("scene.json"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(out()));
}

TEST_F(Cli, SyntaxErrorExitsTwoWithLineAndColumn) {
  const fs::path file = dir_ / "broken.json";
  std::ofstream(file) << "{\n  \"name\": \"x\",\n  \"duration\": ,\n}\n";
  const Outcome run = chainmail("run " + file.string() + " --quiet --out " + out());
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.output.find("line 3"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(out()));
}

TEST_F(Cli, BadOverrideAndBadFlagsExitTwo) {
  const std::string file = scene();
  const Outcome bad_set =
      chainmail("run " + file + " --set backends.plausible.iterations=0 --out " + out());
  EXPECT_EQ(bad_set.status, 2);
  EXPECT_NE(bad_set.output.find("backends.plausible.iterations"), std::string::npos)
      << bad_set.output;
  const Outcome bad_backend = chainmail("run " + file + " --backends nosuch --out " + out());
  EXPECT_EQ(bad_backend.status, 2);
  EXPECT_NE(bad_backend.output.find("nosuch"), std::string::npos) << bad_backend.output;
  EXPECT_EQ(chainmail("run " + file + " --no-such-flag").status, 2);
  EXPECT_EQ(chainmail("run").status, 2);  // the scene is required
  EXPECT_EQ(chainmail("sweep " + file + " --vary nonsense").status, 2);
  EXPECT_FALSE(fs::exists(out()));
}

// a 4 x 4 sheet of torus_xpbd dropped on a round table, as table_cloth's is
TEST_F(Cli, FrictionLawIsAChoiceKnobSetByNameThatChangesTheRun) {
  const std::string file =
      scene({{"weave", {{"plane", "xz"}, {"center", {0.0, 0.105, 0.0}}}},
             {"pins", json::array()},
             {"colliders", json::array({{{"type", "cylinder"},
                                         {"center", {0.0, 0.05, 0.0}},
                                         {"radius", 0.012},
                                         {"half_height", 0.05},
                                         {"friction", 0.4}}})},
             {"duration", 0.1},
             {"reference", "torus_xpbd"},
             {"backends", {{"plausible", nullptr}, {"torus_xpbd", json::object()}}}});
  const auto run = [&](const std::string& law, const std::string& folder) {
    const std::string set = law.empty() ? "" : " --set backends.torus_xpbd.friction_law=" + law;
    const Outcome outcome =
        chainmail("run " + file + set + " --quiet --out " + (dir_ / folder).string() + cache());
    EXPECT_EQ(outcome.status, 0) << outcome.output;
    return json::parse(std::ifstream(dir_ / folder / "summary.json"))["backends"]["torus_xpbd"];
  };
  const json fallback = run("", "default"), cone = run("cone", "cone"),
             pyramid = run("pyramid", "pyramid");
  EXPECT_EQ(fallback["knobs"]["friction_law"], "cone");  // summary.json gives the name
  EXPECT_EQ(pyramid["knobs"]["friction_law"], "pyramid");
  EXPECT_EQ(cone["hash"], fallback["hash"]);
  EXPECT_NE(pyramid["hash"], cone["hash"]);

  // any other value: exit 2, one line naming the key and every name, nothing written
  for (const std::string bad : {"sphere", "1", "true"}) {
    const Outcome refused =
        chainmail("run " + file + " --set backends.torus_xpbd.friction_law=" + bad +
                  " --quiet --out " + out());
    EXPECT_EQ(refused.status, 2) << bad;
    EXPECT_EQ(lines(refused.output), 1) << refused.output;
    EXPECT_NE(refused.output.find("key 'backends.torus_xpbd.friction_law': must be one of "
                                  "\"cone\", \"pyramid\""),
              std::string::npos)
        << refused.output;
  }
  EXPECT_FALSE(fs::exists(out()));
}

TEST_F(Cli, UnstableRunExitsOneWithItsVerdictWritten) {
  // a time step far too large for stiff repulsion (Run.InjectedInstabilityIsReportedNotCrashed
  // says why it is max_speed): the run ends with that verdict, files written
  const std::string file = scene({{"weave", {{"rows", 8}, {"cols", 8}, {"plane", "xz"}}},
                                  {"pins", json::array()},
                                  {"duration", 1.0},
                                  {"backends",
                                   {{"plausible",
                                     {{"dt", 0.05},
                                      {"repulsion_spring", true},
                                      {"newton_steps", 0},
                                      {"iterations", 1},
                                      {"repulsion_stiffness", 1e6},
                                      {"repulsion_fraction", 1.5}}}}}});
  const Outcome run = chainmail("run " + file + " --quiet --out " + out() + cache());
  ASSERT_EQ(run.status, 1) << run.output;
  std::ifstream in(fs::path(out()) / "summary.json");
  const json summary = json::parse(in);
  const json& entry = summary["backends"]["plausible"];
  EXPECT_FALSE(entry["stable"].get<bool>());
  EXPECT_EQ(entry["verdict"], "max_speed");
  EXPECT_NE(run.output.find("max_speed"), std::string::npos) << run.output;
}

TEST_F(Cli, BackendsNotBuiltAreRefusedWhenAskedForAndSkippedWhenTheSceneNamesThem) {
  std::string unbuilt;
  for (const auto& name : known_backend_names()) {
    if (!backend_built(name)) unbuilt = name;
  }
  if (unbuilt.empty()) GTEST_SKIP() << "every backend is built into this binary";
  const Outcome listed =
      chainmail("run " + scene() + " --backends " + unbuilt + " --quiet --out " + out() + cache());
  EXPECT_EQ(listed.status, 2);
  EXPECT_EQ(lines(listed.output), 1) << listed.output;
  EXPECT_NE(listed.output.find(unbuilt + " is not built into this binary (built: "),
            std::string::npos)
      << listed.output;
  EXPECT_FALSE(fs::exists(out()));
  // a scene that configures it and measures drape_rms against it runs the rest, with a note each
  const std::string file =
      scene({{"reference", unbuilt}, {"backends", {{unbuilt, {{"dt", 0.001}}}}}});
  const Outcome run = chainmail("run " + file + " --quiet --out " + out() + cache());
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("cli: " + unbuilt + " not built into this binary: skipped"),
            std::string::npos)
      << run.output;
  EXPECT_NE(
      run.output.find("cli: reference " + unbuilt + " is not built into this binary: no drape_rms"),
      std::string::npos)
      << run.output;
  std::ifstream in(fs::path(out()) / "summary.json");
  const json summary = json::parse(in);
  EXPECT_EQ(summary["reference"],
            "no reference run (" + unbuilt + " is not built into this binary): drape_rms absent");
  EXPECT_TRUE(summary["backends"].contains("plausible"));
  EXPECT_FALSE(summary["backends"].contains(unbuilt));
  EXPECT_FALSE(summary["backends"]["plausible"]["final"].contains("drape_rms"));
}

TEST_F(Cli, RenderWritesOnePanelImagePerSample) {
  const Outcome run = chainmail("run " + scene() + " --render --quiet --out " + out() + cache());
  // a build or a machine without GL says so on one line, exit 2: nothing to check here then
  if (run.status == 2 && run.output.find("--render:") != std::string::npos) {
    GTEST_SKIP() << "no renderer here: " << run.output;
  }
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_TRUE(fs::exists(fs::path(out()) / "images" / "00000.png"));
  EXPECT_TRUE(fs::exists(fs::path(out()) / "images" / "00005.png"));  // 0.05 s at 0.01 s samples
  // an unknown material is bad input, refused before anything runs
  const Outcome bad =
      chainmail("run " + scene() + " --render --material unobtainium --quiet --out " +
                (dir_ / "bad").string() + cache());
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("unobtainium"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
}

TEST_F(Cli, LongRunStaysWithinAMemoryLimitTheOldRunnerExceeded) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space: no limit applies";
#else
  // 4 rings for 400 s sampled every step: 100,001 samples. Keeping every sample's frame (the old
  // runner) needed about 100 MB; streamed, the run's memory does not depend on its duration
  const std::string file = scene(
      {{"weave", {{"rows", 2}, {"cols", 2}}}, {"duration", 400.0}, {"sample_interval", 0.004}});
  const Outcome run =
      chainmail("run " + file + " --quiet --cache none --out " + out(), "ulimit -v 65536;");
  ASSERT_EQ(run.status, 0) << run.output;
  std::ifstream csv(fs::path(out()) / "metrics.csv");
  int rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, 1 + 100001);
#endif
}

TEST_F(Cli, InterruptWritesWhatFinishedAndExits130) {
  // a run far too long to finish: a signal stops it, and what it has is written
  const std::string file =
      scene({{"weave", {{"rows", 6}, {"cols", 6}}},
             {"duration", 600.0},
             {"backends", {{"plausible", json::object()}, {"massspring", json::object()}}}});
  for (const char* signal : {"INT", "TERM"}) {
    fs::remove_all(out());
    const std::string line = std::string(CHAINMAIL_BINARY_DIR "/bench/chainmail run ") + file +
                             " --quiet --cache none --reference none --out " + out() +
                             " & pid=$!; sleep 2; kill -" + signal + " $pid; wait $pid";
    const Outcome interrupted = chainmail_shell(line);
    EXPECT_EQ(interrupted.status, 130) << interrupted.output;
    std::ifstream in(fs::path(out()) / "summary.json");
    const json summary = json::parse(in, nullptr, false);
    ASSERT_FALSE(summary.is_discarded()) << interrupted.output;
    EXPECT_TRUE(summary["interrupted"].get<bool>());
    EXPECT_EQ(summary["backends"]["plausible"]["verdict"], "interrupted");
    EXPECT_EQ(summary["backends"]["massspring"]["verdict"], "interrupted");
    // the sample where it stopped is written once: times strictly increase, one row per sample
    std::ifstream csv(fs::path(out()) / "metrics.csv");
    std::string row;
    std::getline(csv, row);
    double last_t = -1.0;
    long long rows = 0;
    while (std::getline(csv, row)) {
      const double t = std::stod(row.substr(row.find(',') + 1));
      EXPECT_GT(t, last_t) << row;
      last_t = t, ++rows;
    }
    EXPECT_EQ(rows, summary["backends"]["plausible"]["samples"].get<long long>());
    for (const auto& e : fs::directory_iterator(dir_))
      EXPECT_EQ(e.path().filename().string().find(".partial-"), std::string::npos) << e.path();
  }
}

TEST_F(Cli, DefaultOutputIsTheScenesRunFolderAndNeverTheBenchs) {
  const std::string file = scene();
  const Outcome run =
      chainmail("run " + file + " --quiet --cache none", "cd " + dir_.string() + " &&");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_TRUE(fs::exists(dir_ / "results" / "cli" / "run" / "summary.json"));
  EXPECT_TRUE(fs::exists(dir_ / "results" / "cli" / "run" / ".chainmail-manifest.json"));
  // a user's file in the run folder stops the next run from replacing it
  std::ofstream(dir_ / "results" / "cli" / "run" / "notes.md") << "mine";
  const Outcome again =
      chainmail("run " + file + " --quiet --cache none", "cd " + dir_.string() + " &&");
  EXPECT_EQ(again.status, 2) << again.output;
  EXPECT_NE(again.output.find("notes.md"), std::string::npos) << again.output;
  EXPECT_TRUE(fs::exists(dir_ / "results" / "cli" / "run" / "notes.md"));
}

TEST_F(Cli, ReferenceRunIsAnnouncedAndCanBeLeftOut) {
  // the reference at a finer dt than the run's own: a run of its own, before the others
  const std::string file = scene({{"reference_dt", 0.002}});
  const Outcome announced = chainmail("run " + file + " --out " + out() + cache());
  ASSERT_EQ(announced.status, 0) << announced.output;
  EXPECT_NE(announced.output.find("reference run: plausible at dt 0.002 s"), std::string::npos)
      << announced.output;
  const Outcome none =
      chainmail("run " + file + " --reference none --out " + out() + "_none" + cache());
  ASSERT_EQ(none.status, 0) << none.output;
  EXPECT_EQ(none.output.find("reference run"), std::string::npos) << none.output;
  std::ifstream in(fs::path(out() + "_none") / "summary.json");
  const json summary = json::parse(in);
  EXPECT_FALSE(summary["backends"]["plausible"]["final"].contains("drape_rms"));
}

TEST_F(Cli, UnwritableCacheWarnsOnceAndTheRunGoesOn) {
  const Outcome run = chainmail("run " + scene({{"reference_dt", 0.002}}) +
                                " --quiet --cache /proc/chainmail-cache --out " + out());
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("warning: reference cache"), std::string::npos) << run.output;
  std::ifstream in(fs::path(out()) / "summary.json");
  const json summary = json::parse(in);
  EXPECT_TRUE(summary["backends"]["plausible"]["final"].contains("drape_rms"));
}

// ---------------------------------------------------------------------------------------------
// the commands that run nothing: --version, backends, check, --help

TEST_F(Cli, VersionNamesTheVersionCommitCompilerAndBuildType) {
  const Outcome version = chainmail("--version");
  EXPECT_EQ(version.status, 0);
  EXPECT_EQ(version.output, chainmail_version() + " (" + chainmail_commit() + ", " +
                                chainmail_compiler() + ", " + chainmail_build_type() + ")\n");
}

TEST_F(Cli, BackendsListsEveryKnobWithItsTypeDefaultRangeAndHelp) {
  const Outcome text = chainmail("backends");
  ASSERT_EQ(text.status, 0) << text.output;
  const Outcome as_json = chainmail("backends --json");
  ASSERT_EQ(as_json.status, 0) << as_json.output;
  const json listed = json::parse(as_json.output)["backends"];
  ASSERT_EQ(listed.size(), known_backend_names().size());
  for (std::size_t k = 0; k < listed.size(); ++k) {
    const std::string name = known_backend_names()[k];
    SCOPED_TRACE(name);
    EXPECT_EQ(listed[k]["name"], name);
    EXPECT_EQ(listed[k]["built"], backend_built(name));
    const BackendInfo* info = find_backend(name);
    if (!info) {
      EXPECT_NE(text.output.find(name + ": not built into this binary"), std::string::npos);
      continue;
    }
    EXPECT_NE(text.output.find(name + ": " + info->summary + "\n"), std::string::npos);
    ASSERT_EQ(listed[k]["knobs"].size(), info->knobs.size());
    for (std::size_t n = 0; n < info->knobs.size(); ++n) {
      const KnobSpec& spec = info->knobs[n];
      const json& knob = listed[k]["knobs"][n];
      EXPECT_EQ(knob["name"], spec.name);
      EXPECT_EQ(knob["help"], spec.help);
      EXPECT_EQ(knob["unit"], spec.unit);
      EXPECT_EQ(knob["doc"], spec.doc.empty() ? spec.help : spec.doc);
      if (spec.type == KnobSpec::Type::choice) {  // the default by name, and every name
        EXPECT_EQ(knob["type"], "choice");
        EXPECT_EQ(knob["default"], choice_name(spec, spec.default_value)) << spec.name;
        EXPECT_EQ(knob["choices"], json(spec.choices)) << spec.name;
        EXPECT_FALSE(knob.contains("min")) << spec.name;
        std::string names;
        for (const std::string& name : spec.choices) names.append(names.empty() ? "" : "|") += name;
        EXPECT_NE(text.output.find(" " + names + " "), std::string::npos) << spec.name;
        continue;
      }
      if (spec.type == KnobSpec::Type::boolean) {
        EXPECT_EQ(knob["type"], "boolean");
        EXPECT_EQ(knob["default"], spec.default_value != 0.0) << spec.name;
        continue;
      }
      EXPECT_EQ(knob["default"].get<double>(), spec.default_value) << spec.name;
      EXPECT_EQ(knob["min"].get<double>(), spec.min) << spec.name;
      EXPECT_EQ(knob["max"].get<double>(), spec.max) << spec.name;
      EXPECT_NE(text.output.find("  " + spec.name + " "), std::string::npos) << spec.name;
      EXPECT_NE(text.output.find(spec.help + "\n"), std::string::npos) << spec.name;
    }
  }
}

TEST_F(Cli, CheckValidatesScenesAndWritesNothing) {
  const std::string good = scene();
  const Outcome ok =
      chainmail("check " + good + " --set weave.rows=3", "cd " + dir_.string() + " &&");
  ASSERT_EQ(ok.status, 0) << ok.output;
  EXPECT_EQ(ok.output, good +
                           ": ok: scene 'cli', 12 rings (4in1 3 x 4), 0.05 s; backends "
                           "plausible; reference plausible\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);

  // every file is checked; one bad file is bad input
  const fs::path bad = dir_ / "bad.json";
  std::ofstream(bad) << R"({"name": "bad", "weave": {"type": "chain", "cols": 1}, "duration": 1})";
  const Outcome both = chainmail("check " + bad.string() + " " + good);
  EXPECT_EQ(both.status, 2);
  EXPECT_NE(both.output.find("chainmail: " + bad.string() + ": key 'weave.cols': must be in [2, "),
            std::string::npos)
      << both.output;
  EXPECT_NE(both.output.find(good + ": ok: "), std::string::npos) << both.output;
  EXPECT_EQ(lines(both.output), 2) << both.output;
  const Outcome bad_set = chainmail("check " + good + " --set backends.plausible.dt=1");
  EXPECT_EQ(bad_set.status, 2);
  EXPECT_NE(bad_set.output.find("backends.plausible.dt"), std::string::npos) << bad_set.output;

  // the resolved scene, every default filled in
  const Outcome resolved = chainmail("check --resolved " + good);
  ASSERT_EQ(resolved.status, 0) << resolved.output;
  EXPECT_EQ(json::parse(resolved.output), scene_to_json(load_scene_file(good)));
}

TEST_F(Cli, HelpShowsDefaultsAndTheBackends) {
  const Outcome run = chainmail("run --help");
  EXPECT_EQ(run.status, 0);
  for (const char* shown : {"--max-memory FLOAT=8", "--max-hours FLOAT=2", "--max-output FLOAT=20",
                            "--shader TEXT=texture", "--material TEXT=steel"})
    EXPECT_NE(run.output.find(shown), std::string::npos) << shown << "\n" << run.output;
  for (const std::string& name : known_backend_names())
    EXPECT_NE(run.output.find(" " + name), std::string::npos) << name;
  EXPECT_NE(chainmail("bench --help").output.find("--jobs INT:INT in [1 - 256]=2"),
            std::string::npos);
  EXPECT_NE(chainmail("stability --help").output.find("--max-wall FLOAT=30"), std::string::npos);
  const Outcome top = chainmail("--help");
  for (const char* listed : {"backends", "check", "Exit status: 0 ok", "Bench scenes: "})
    EXPECT_NE(top.output.find(listed), std::string::npos) << listed;
}

}  // namespace
}  // namespace chainmail

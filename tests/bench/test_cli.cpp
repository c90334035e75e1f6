// The chainmail command as a user meets it: exit statuses, one message naming the key, nothing
// written on bad input, and the files a good run leaves.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

namespace chainmail {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

struct Outcome {
  int status = -1;     // exit status
  std::string output;  // stdout and stderr together
};

Outcome chainmail(const std::string& arguments, const std::string& environment = "") {
  const std::string line =
      environment + " " + CHAINMAIL_BINARY_DIR "/bench/chainmail " + arguments + " 2>&1";
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

int lines(const std::string& text) {
  int count = 0;
  for (char ch : text) count += ch == '\n';
  return count;
}

class Cli : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
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

TEST_F(Cli, UnstableRunExitsOneWithItsVerdictWritten) {
  // a time step far too large for stiff repulsion: the run must end with a verdict, files written
  const std::string file =
      scene({{"weave", {{"rows", 8}, {"cols", 8}, {"plane", "xz"}}},
             {"pins", json::array()},
             {"duration", 1.0},
             {"backends",
              {{"plausible",
                {{"dt", 0.05}, {"repulsion_stiffness", 1e6}, {"repulsion_fraction", 1.5}}}}}});
  const Outcome run = chainmail("run " + file + " --quiet --out " + out() + cache());
  ASSERT_EQ(run.status, 1) << run.output;
  std::ifstream in(fs::path(out()) / "summary.json");
  const json summary = json::parse(in);
  const json& entry = summary["backends"]["plausible"];
  EXPECT_FALSE(entry["stable"].get<bool>());
  const std::string verdict = entry["verdict"];
  EXPECT_TRUE(verdict == "non_finite" || verdict == "max_speed" || verdict == "energy_growth" ||
              verdict == "torn_links")
      << verdict;
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

}  // namespace
}  // namespace chainmail

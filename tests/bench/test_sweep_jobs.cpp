// A sweep run elsewhere: the printed jobs run one by one and gathered give the local sweep's
// table; --gather refuses missing points and points of another sweep; the Slurm script.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bench/harness/commands/commands.hpp"
#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/output/output_folder.hpp"
#include "bench/harness/suites/process.hpp"
#include "bench/harness/suites/sweep.hpp"
#include "test_temp.hpp"

namespace chainmail {
namespace {

namespace fs = std::filesystem;
using Strings = std::vector<std::string>;

Strings lines_of(const std::string& text) {
  Strings lines;
  std::stringstream stream(text);
  for (std::string line; std::getline(stream, line);)
    if (!line.empty()) lines.push_back(line);
  return lines;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// sweep.csv without the two timing columns (wall_per_sim_s, ms_per_step)
Strings without_timings(const std::string& csv) {
  Strings rows;
  for (const std::string& line : lines_of(csv)) {
    std::vector<std::string> cells;
    std::stringstream stream(line);
    for (std::string cell; std::getline(stream, cell, ',');) cells.push_back(cell);
    cells.erase(cells.begin() + 2, cells.begin() + 4);
    std::string row;
    for (const auto& c : cells) row += c + ",";
    rows.push_back(row);
  }
  return rows;
}

class SweepJobs : public testing::Test {
 protected:
  void SetUp() override {
    // a folder per test: ctest runs them side by side
    root = chainmail::test_temp_root() /
           ("chainmail_test_sweep_jobs_" +
            std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(root);
    fs::create_directories(root);
    sweep.scene_file = CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json";
    sweep.overrides = {"weave.rows=4", "weave.cols=4", "duration=0.04", "reference=plausible"};
    sweep.vary = {"backends.{backend}.dt=0.004,0.002"};
    sweep.backends = {"plausible", "massspring"};
    sweep.executable = CHAINMAIL_BINARY_DIR "/bench/chainmail";
    sweep.progress = false;
    sweep.cache_dir = (root / "cache").string();
  }
  void TearDown() override { fs::remove_all(root); }

  // the printed jobs run one after another, as GNU parallel or a scheduler would
  void run_printed_jobs(const std::string& out) {
    SweepCommand print = sweep;
    print.print_jobs = true;
    print.out_dir = out;
    testing::internal::CaptureStdout();
    ASSERT_EQ(sweep_command(print), kExitOk);
    const Strings jobs = lines_of(testing::internal::GetCapturedStdout());
    ASSERT_EQ(jobs.size(), 1u + 4u);  // the reference, then 2 backends x 2 dts
    // exit 1: the point's run was unstable, a finding that sweep.csv records
    for (const auto& job : jobs) {
      const int status = std::system((job + " 2>/dev/null").c_str());
      ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) <= 1) << job;
    }
  }

  fs::path root;
  SweepCommand sweep;
};

TEST_F(SweepJobs, GatheredPointsGiveTheLocalSweepsTable) {
  SweepCommand local = sweep;
  local.out_dir = (root / "local").string();
  ASSERT_EQ(sweep_command(local), kExitOk);
  const std::string jobs = (root / "jobs").string();
  run_printed_jobs(jobs);
  SweepCommand gather = sweep;
  gather.gather = jobs;
  ASSERT_EQ(sweep_command(gather), kExitOk);
  EXPECT_EQ(without_timings(read_text(root / "jobs/sweep.csv")),
            without_timings(read_text(root / "local/sweep.csv")));
  for (int k = 0; k < 4; ++k) {
    const std::string point = "/points/" + std::to_string(k) + "/summary.json";
    const std::string a = read_text(root / ("local" + point)), b = read_text(jobs + point);
    const auto hash = [](const std::string& s) { return s.substr(s.find("\"hash\""), 30); };
    EXPECT_EQ(hash(a), hash(b)) << point;
  }
  // the gathered folder is a sweep's: a local sweep may replace it, and gathering again works
  EXPECT_EQ(replace_refusal(jobs, "sweep", false), "");
  EXPECT_EQ(sweep_command(gather), kExitOk);
}

TEST_F(SweepJobs, GatherRefusesMissingPointsAndPointsOfAnotherSweep) {
  const std::string jobs = (root / "jobs").string();
  run_printed_jobs(jobs);
  SweepCommand other = sweep;
  other.gather = jobs;
  other.vary = {"backends.{backend}.dt=0.004,0.001"};
  EXPECT_THROW(
      {
        try {
          sweep_command(other);
        } catch (const UsageError& e) {
          EXPECT_NE(std::string(e.what()).find("from another sweep"), std::string::npos);
          EXPECT_NE(std::string(e.what()).find("backends.plausible.dt"), std::string::npos);
          throw;
        }
      },
      UsageError);
  EXPECT_FALSE(fs::exists(root / "jobs/sweep.csv"));
  fs::remove_all(root / "jobs/points/2");
  SweepCommand gather = sweep;
  gather.gather = jobs;
  EXPECT_THROW(sweep_command(gather), UsageError);
  EXPECT_FALSE(fs::exists(root / "jobs/sweep.csv"));
}

TEST_F(SweepJobs, SlurmScriptReferenceThenArrayThenGatherAllAbsolute) {
  const fs::path script = root / "sweep.sbatch";
  SweepCommand slurm = sweep;
  slurm.slurm = script.string();
  slurm.out_dir = "relative_jobs";
  ASSERT_EQ(sweep_command(slurm), kExitOk);
  const std::string text = read_text(script);
  const auto at = [&](const std::string& what) { return text.find(what); };
  ASSERT_NE(at("--reference-only"), std::string::npos);
  EXPECT_LT(at("--reference-only"), at("--array=0-3"));
  EXPECT_LT(at("--array=0-3"), at("--dependency=afterok:"));
  EXPECT_LT(at("--dependency=afterok:"), at("--gather"));
  EXPECT_NE(at("--gather " + (fs::current_path() / "relative_jobs").string()), std::string::npos);
  EXPECT_NE(at("--cpus-per-task=1"), std::string::npos);
  EXPECT_NE(at("  3) exec "), std::string::npos);
  EXPECT_EQ(at("--out relative_jobs"), std::string::npos);  // every path absolute
  EXPECT_EQ(std::system(("bash -n " + script.string()).c_str()), 0);
  // its own script is rewritten; a file chainmail did not write is refused
  EXPECT_EQ(sweep_command(slurm), kExitOk);
  std::ofstream(root / "mine.sh") << "#!/bin/sh\necho mine\n";
  slurm.slurm = (root / "mine.sh").string();
  EXPECT_THROW(sweep_command(slurm), UsageError);
  EXPECT_EQ(read_text(root / "mine.sh"), "#!/bin/sh\necho mine\n");
  slurm.cache_dir = kNoCache;  // the points need the reference in a shared cache
  fs::remove(script);
  slurm.slurm = script.string();
  EXPECT_THROW(sweep_command(slurm), UsageError);
}

}  // namespace
}  // namespace chainmail

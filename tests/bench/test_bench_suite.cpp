// The main bench: its plan, and a quick bench writing every results file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "bench/harness/bench_suite.hpp"
#include "bench/harness/budget.hpp"
#include "bench/harness/commands.hpp"
#include "bench/harness/process.hpp"
#include "bench/harness/scene_file.hpp"
#include "bench/harness/sweep.hpp"

namespace chainmail {
namespace {

namespace fs = std::filesystem;

int count_lines(const fs::path& path) {
  std::ifstream in(path);
  int lines = 0;
  for (std::string line; std::getline(in, line);) lines += !line.empty();
  return lines;
}

TEST(BenchPlan, EveryStepLoadsAndQuickModeIsSmallerAndShorter) {
  const BenchPlan& plan = bench_plan();
  EXPECT_EQ(plan.scenes.size(), 6u);
  EXPECT_EQ(plan.sweeps.size(), 3u);
  std::vector<BenchStep> steps = plan.scenes;
  steps.insert(steps.end(), plan.sweeps.begin(), plan.sweeps.end());
  for (const BenchStep& step : steps) {
    SCOPED_TRACE(step.file);
    const std::string file = CHAINMAIL_SOURCE_DIR "/bench/scenes/" + step.file;
    const Scene full = load_scene_file(file, step.overrides(false));
    const Scene quick = load_scene_file(file, step.overrides(true));
    EXPECT_LT(ring_count(quick), ring_count(full));
    EXPECT_LT(quick.duration, full.duration);
  }
  // the sweeps: five dts per backend, two in quick mode
  EXPECT_EQ(sweep_grid(parse_vary({plan.vary}), {"plausible"}).size(), 5u);
  EXPECT_EQ(sweep_grid(parse_vary({plan.quick_vary}), {"plausible"}).size(), 2u);
  EXPECT_LT(plan.quick_stability_watchdog_s, plan.stability_watchdog_s);
}

TEST(Bench, QuickModeWritesEveryResultsFile) {
  const fs::path out = fs::temp_directory_path() / "chainmail_test_bench";
  fs::remove_all(out);
  BenchCommand bench;
  bench.out_dir = out.string();
  bench.quick = true;
  bench.backends = {"plausible", "massspring"};  // massspring brings the stiffness study
  bench.executable = CHAINMAIL_BINARY_DIR "/bench/chainmail";
  bench.render = false;
  bench.progress = false;
  ASSERT_EQ(bench_command(bench), kExitOk);
  for (const char* file :
       {"README.md", "timing.md", "timing.csv", "metrics.md", "sweep/curtain/sweep.csv",
        "sweep/table_cloth/sweep.csv", "sweep/corner_hang/sweep.csv", "stability/stability.md",
        "stability/stability.csv", "curtain/summary.json", "corner_hang/summary.json",
        "table_cloth/metrics.csv", "chain_catenary/table.md", "chain_pile/summary.json",
        "sphere_drape/summary.json"}) {
    EXPECT_TRUE(fs::exists(out / file)) << file;
  }
  EXPECT_EQ(count_lines(out / "timing.csv"), 1 + 6 * 2);  // six scenes, two backends
  if (!plotting_python().empty()) {
    EXPECT_TRUE(fs::exists(out / "sweep/curtain/sweep.png"));
    EXPECT_TRUE(fs::exists(out / "sweep/table_cloth/sweep.png"));
    EXPECT_TRUE(fs::exists(out / "sweep/corner_hang/sweep.png"));
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

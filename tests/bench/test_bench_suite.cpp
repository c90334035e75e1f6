// The main bench: its plan, and a quick bench writing every results file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "backends/backend.hpp"
#include "bench/harness/commands/commands.hpp"
#include "bench/harness/run/budget.hpp"
#include "bench/harness/suites/bench_suite.hpp"
#include "bench/harness/suites/process.hpp"
#include "bench/harness/suites/scaling.hpp"
#include "bench/harness/suites/sweep.hpp"
#include "scene_file/scene_file.hpp"
#include "test_temp.hpp"

namespace chainmail {
namespace {

namespace fs = std::filesystem;

int count_lines(const fs::path& path) {
  std::ifstream in(path);
  int lines = 0;
  for (std::string line; std::getline(in, line);) lines += !line.empty();
  return lines;
}

TEST(Scaling, PlanCoversTheSizesUpToTheLargestAsked) {
  EXPECT_EQ(scaling_plan(false, 256).sides, (std::vector<int>{16, 32, 64, 128, 256}));
  EXPECT_EQ(scaling_plan(false, 64).sides, (std::vector<int>{16, 32, 64}));
  EXPECT_EQ(scaling_plan(false, 256).threads, (std::vector<int>{1, 2}));
  EXPECT_LT(scaling_plan(true, 256).duration, scaling_plan(false, 256).duration);
}

TEST(Scaling, TableHasEverySizeOnEachThreadCountWithOneHashPerSize) {
  // the quick plan through the real runs: a row per size and thread count for plausible, the
  // same final hash on 1 and 2 threads, costs that are positive, and the speed-up column filled
  // for the 2-thread rows only
  const fs::path out = chainmail::test_temp_root() / "chainmail_test_scaling";
  fs::remove_all(out);
  fs::create_directories(out);
  const std::string table =
      run_scaling(scaling_plan(true, 256), CHAINMAIL_SOURCE_DIR "/bench/scenes", {"plausible"},
                  out.string(), false);
  EXPECT_NE(table.find("| plausible | 8 × 8 | 2 |"), std::string::npos) << table;
  std::ifstream csv(out / "scaling.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("backend,side,rings,threads,runs,steps,dt,ms_per_step", 0), 0u);
  std::map<std::string, std::set<std::string>> hashes;  // side -> hashes over thread counts
  int rows = 0;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 15u) << line;  // no ODE run: cost_vs_ode empty (getline drops it)
    ++rows;
    EXPECT_EQ(cells[0], "plausible");
    EXPECT_GT(std::stod(cells[7]), 0.0);            // ms_per_step
    EXPECT_EQ(cells[10].empty(), cells[3] == "1");  // speed-up on more threads only
    EXPECT_EQ(cells[14], "true");
    hashes[cells[1]].insert(cells[13]);
  }
  EXPECT_EQ(rows, 4);
  for (const auto& [side, found] : hashes) EXPECT_EQ(found.size(), 1u) << side;
  fs::remove_all(out);
}

TEST(Scaling, BackendsThatStepOnSeveralThreadsGetARowPerThreadCount) {
  // torus_xpbd steps on the threads it is given, massspring on one
  ASSERT_TRUE(find_backend("torus_xpbd")->multithreaded);
  ASSERT_FALSE(find_backend("massspring")->multithreaded);
  const fs::path out = chainmail::test_temp_root() / "chainmail_test_scaling_threads";
  fs::remove_all(out);
  fs::create_directories(out);
  ScalingPlan plan = scaling_plan(true, 4);
  const std::string table = run_scaling(plan, CHAINMAIL_SOURCE_DIR "/bench/scenes",
                                        {"torus_xpbd", "massspring"}, out.string(), false);
  EXPECT_NE(table.find("| torus_xpbd | 4 × 4 | 1 |"), std::string::npos) << table;
  EXPECT_NE(table.find("| torus_xpbd | 4 × 4 | 2 |"), std::string::npos) << table;
  EXPECT_NE(table.find("| massspring | 4 × 4 | 1 |"), std::string::npos) << table;
  EXPECT_EQ(table.find("| massspring | 4 × 4 | 2 |"), std::string::npos) << table;
  fs::remove_all(out);
}

// plausible's quick scaling plan up to max_side with two runs per cell: its progress lines
// (after "bench: scaling plausible ") in order, and its CSV rows split into cells
struct ScalingRounds {
  std::vector<std::string> order;
  std::vector<std::vector<std::string>> rows;
  std::string progress;
};
ScalingRounds plausible_rounds(int max_side, const std::string& folder) {
  ScalingPlan plan = scaling_plan(true, max_side);
  plan.plausible_repeats = 2;
  const fs::path out = chainmail::test_temp_root() / folder;
  fs::remove_all(out);
  fs::create_directories(out);
  testing::internal::CaptureStderr();
  run_scaling(plan, CHAINMAIL_SOURCE_DIR "/bench/scenes", {"plausible"}, out.string(), true);
  ScalingRounds rounds;
  rounds.progress = testing::internal::GetCapturedStderr();
  std::stringstream lines(rounds.progress);
  const std::string prefix = "bench: scaling plausible ";
  for (std::string line; std::getline(lines, line);)
    if (line.find(prefix) == 0) rounds.order.push_back(line.substr(prefix.size()));
  std::ifstream csv(out / "scaling.csv");
  std::string line;
  for (std::getline(csv, line); std::getline(csv, line);) {
    std::vector<std::string>& cells = rounds.rows.emplace_back();
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
  }
  fs::remove_all(out);
  return rounds;
}

TEST(Scaling, RepeatsGoRoundTheThreadCountsSoASlowSpellFallsOnAll) {
  // two runs per cell: 1 thread, 2 threads, 1 thread, 2 threads (not 1, 1, 2, 2), each cell the
  // median of its own two
  const ScalingRounds rounds = plausible_rounds(4, "chainmail_test_scaling_rounds");
  EXPECT_EQ(rounds.order, (std::vector<std::string>{
                              "4 x 4 on 1 thread (run 1 of 2)", "4 x 4 on 2 threads (run 1 of 2)",
                              "4 x 4 on 1 thread (run 2 of 2)", "4 x 4 on 2 threads (run 2 of 2)"}))
      << rounds.progress;
  ASSERT_EQ(rounds.rows.size(), 2u);
  for (const std::vector<std::string>& cells : rounds.rows) {
    ASSERT_GT(cells.size(), 4u);
    EXPECT_EQ(cells[1], "4");
    EXPECT_EQ(cells[4], "2");  // runs
  }
}

TEST(Scaling, RepeatsGoRoundTheSizesSoTheirRatiosCompareLikeWithLike) {
  // two sizes, two runs per cell: 4 x 4 on 1 and 2 threads, 8 x 8 on 1 and 2, then again (not
  // every run of 4 x 4 before the first of 8 x 8)
  ASSERT_EQ(scaling_plan(true, 8).sides, (std::vector<int>{4, 8}));
  const ScalingRounds rounds = plausible_rounds(8, "chainmail_test_scaling_sizes");
  EXPECT_EQ(rounds.order, (std::vector<std::string>{
                              "4 x 4 on 1 thread (run 1 of 2)", "4 x 4 on 2 threads (run 1 of 2)",
                              "8 x 8 on 1 thread (run 1 of 2)", "8 x 8 on 2 threads (run 1 of 2)",
                              "4 x 4 on 1 thread (run 2 of 2)", "4 x 4 on 2 threads (run 2 of 2)",
                              "8 x 8 on 1 thread (run 2 of 2)", "8 x 8 on 2 threads (run 2 of 2)"}))
      << rounds.progress;
  ASSERT_EQ(rounds.rows.size(), 4u);
  for (const std::vector<std::string>& cells : rounds.rows) {
    ASSERT_GT(cells.size(), 4u);
    EXPECT_EQ(cells[4], "2");  // runs: two each
  }
}

TEST(Scaling, RunsGoRoundTheBackendsAndCostsAreRelativeToOdesOnOneThread) {
  // two runs per cell, in rounds over the backends and thread counts (ode, torus_xpbd on 1 and
  // 2 threads, then again), and each cell's cost per simulated second over ODE's
  if (!backend_built("ode")) GTEST_SKIP() << "ode is not built into this binary";
  ScalingPlan plan = scaling_plan(true, 4);
  plan.repeats = 2;
  const fs::path out = chainmail::test_temp_root() / "chainmail_test_scaling_vs_ode";
  fs::remove_all(out);
  fs::create_directories(out);
  testing::internal::CaptureStderr();
  const std::string table = run_scaling(plan, CHAINMAIL_SOURCE_DIR "/bench/scenes",
                                        {"ode", "torus_xpbd"}, out.string(), true);
  const std::string progress = testing::internal::GetCapturedStderr();
  std::vector<std::string> order;
  std::stringstream lines(progress);
  for (std::string line; std::getline(lines, line);)
    if (line.find("bench: scaling ") == 0) order.push_back(line.substr(15));
  EXPECT_EQ(order, (std::vector<std::string>{
                       "ode 4 x 4 on 1 thread (run 1 of 2)",
                       "torus_xpbd 4 x 4 on 1 thread (run 1 of 2)",
                       "torus_xpbd 4 x 4 on 2 threads (run 1 of 2)",
                       "ode 4 x 4 on 1 thread (run 2 of 2)",
                       "torus_xpbd 4 x 4 on 1 thread (run 2 of 2)",
                       "torus_xpbd 4 x 4 on 2 threads (run 2 of 2)",
                   }))
      << progress;
  std::ifstream csv(out / "scaling.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_NE(header.find(",cost_vs_ode"), std::string::npos) << header;
  std::map<std::string, double> seconds_per_simulated;  // backend and threads -> ms/step / dt
  std::map<std::string, double> vs_ode;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 16u) << line;
    EXPECT_EQ(cells[4], "2") << line;  // runs
    const std::string key = cells[0] + "/" + cells[3];
    seconds_per_simulated[key] = std::stod(cells[7]) / std::stod(cells[6]);
    vs_ode[key] = std::stod(cells[15]);
  }
  ASSERT_EQ(vs_ode.size(), 3u);
  EXPECT_DOUBLE_EQ(vs_ode["ode/1"], 1.0);
  for (const std::string key : {"torus_xpbd/1", "torus_xpbd/2"})
    EXPECT_NEAR(vs_ode[key], seconds_per_simulated[key] / seconds_per_simulated["ode/1"],
                1e-5 * vs_ode[key])
        << key;
  EXPECT_NE(table.find("| cost vs ODE |"), std::string::npos) << table;
  fs::remove_all(out);
}

TEST(BenchPlan, EveryStepLoadsAndQuickModeIsSmallerAndShorter) {
  const BenchPlan& plan = bench_plan();
  EXPECT_EQ(plan.scenes.size(), 6u);
  EXPECT_EQ(plan.sweeps.size(), plan.scenes.size());  // a Pareto front for every scene
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
  const fs::path out = chainmail::test_temp_root() / "chainmail_test_bench";
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
  // the frames of the page's 3D views: every sample of the curtain and the sphere drape only
  for (const char* scene : {"curtain", "sphere_drape"}) {
    for (const char* backend : {"plausible", "massspring"}) {
      const fs::path frames = out / scene / "frames" / backend;
      EXPECT_TRUE(fs::exists(frames / "00000.csv")) << frames;
      EXPECT_TRUE(fs::exists(frames / "00001.csv")) << frames;
    }
  }
  EXPECT_FALSE(fs::exists(out / "corner_hang" / "frames"));
  EXPECT_EQ(count_lines(out / "timing.csv"), 1 + 6 * 2);  // six scenes, two backends
  // both backends are cheap: each row is the median of the quick bench's two runs, which ended on
  // the same state; no ODE run, so no cost relative to it
  std::ifstream timing(out / "timing.csv");
  std::string header;
  std::getline(timing, header);
  EXPECT_EQ(header.substr(header.find(",hash,")), ",hash,runs,hashes_agree,cost_vs_ode");
  for (std::string line; std::getline(timing, line);) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 11u) << line;  // the last, empty cell ends the line
    EXPECT_EQ(cells[9], "2") << line;
    EXPECT_EQ(cells[10], "true") << line;
  }
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

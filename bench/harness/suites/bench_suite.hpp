// The main bench: every bench scene through every backend, the error-against-time sweeps and the
// stability suite, into one folder (results/bench/). What it runs is the plan below.
#pragma once

#include <string>
#include <vector>

namespace chainmail {

struct BenchCommand {
  std::string out_dir = "results/bench";
  bool force = false;
  bool quick = false;  // reduced sizes and durations (test mode)
  std::vector<std::string> backends;
  std::string executable;
  int jobs = 2;
  int threads = 0;
  bool scaling = true;    // the scaling table (scaling.csv, scaling.md, scaling.png)
  int scaling_max = 256;  // its largest sheet, rings a side  // threads of each scene run; 0: every
                          // hardware thread (sweeps: shared by jobs)
  bool render = true;
  bool progress = true;
};
int bench_command(const BenchCommand& command);

// one scene file under bench/scenes/ with the --set overrides of each mode
struct BenchStep {
  std::string file;
  std::vector<std::string> full, quick;
  // keep its frames (frames/<backend>/NNNNN.csv) for the 3D view of the bench's page
  bool frames = false;

  const std::vector<std::string>& overrides(bool quick_mode) const {
    return quick_mode ? quick : full;
  }
};

struct BenchPlan {
  std::vector<BenchStep> scenes;  // each through every backend: timing and metric tables
  std::vector<BenchStep> sweeps;  // error against run time over each backend's dt
  std::string vary, quick_vary;   // the sweeps' --vary
  double stability_watchdog_s = 10.0, quick_stability_watchdog_s = 5.0;  // per run
  // the timing table's runs of each backend whose first run stepped for at most
  // timing_repeat_budget_s (the median of them; one run of the others)
  int timing_runs = 3, quick_timing_runs = 2;
  double timing_repeat_budget_s = 20.0;
};

// what `chainmail bench` runs, in order
const BenchPlan& bench_plan();

}  // namespace chainmail

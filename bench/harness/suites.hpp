// Sweeps (error against run time), the stability suite and the main bench.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "bench/harness/run.hpp"

namespace chainmail {

// relative error of a chain's sag against the catenary of the same span and length
// (length = links x 2(c - a)); absent unless the scene is a chain pinned at both ends
std::optional<double> catenary_error(const Scene& scene, const Weave& weave,
                                     const RingFrame& frame);

struct SweepCommand {
  std::string scene_file;
  std::vector<std::string> vary;      // KEY=v1,v2,...; "{backend}" in KEY stands for each backend
  std::vector<std::string> backends;  // empty: the scene's own list
  std::vector<std::string> overrides;
  std::string out_dir;  // default results/<scene>/sweep
  bool force = false;   // replace a foreign empty folder at out_dir
  int jobs = 1;
  bool print_jobs = false;  // print one `chainmail run` command line per point and stop
  std::string executable;   // the chainmail binary that runs each point
  bool progress = true;
  std::string cache_dir;  // "" = the default cache folder, "none" = no cache
};
int sweep_command(const SweepCommand& command);

struct StabilityCommand {
  std::vector<std::string> backends;  // empty: every backend
  std::string out_dir = "results/stability";
  bool force = false;
  bool quick = false;              // tiny sizes, for tests
  double max_wall_seconds = 30.0;  // watchdog per run
  bool progress = true;
};
int stability_command(const StabilityCommand& command);

struct BenchCommand {
  std::string out_dir = "results/bench";
  bool force = false;
  bool quick = false;  // reduced sizes and durations (test mode)
  std::vector<std::string> backends;
  std::string executable;
  int jobs = 2;
  bool render = true;
  bool progress = true;
};
int bench_command(const BenchCommand& command);

// a python interpreter with matplotlib for the plots ("" when none)
std::string plotting_python();

}  // namespace chainmail

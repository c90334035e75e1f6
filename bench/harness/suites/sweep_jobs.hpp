// What a sweep's jobs share, for the commands that run its points elsewhere: --print-jobs (a
// reference job, then one line per point), --slurm (a submission script) and --gather (the
// points' folders read back into sweep.csv and the plot, as a local sweep writes them).
#pragma once

#include <string>
#include <vector>

#include "bench/harness/suites/sweep_command.hpp"
#include "bench/harness/suites/sweep_grid.hpp"
#include "core/scene.hpp"

namespace chainmail {

// what every point's `chainmail run` command line shares
struct SweepJobs {
  std::string executable, scene_file, cache;  // cache "" = none
  std::vector<std::string> overrides;         // the command's own, before each point's
  std::string reference_set;                  // reference_dt=..., after each point's
  int threads = 1;                            // --threads of each point

  // point k's command line, writing into `folder`/points/k (argv form, no shell in between)
  std::vector<std::string> args(const SweepPoint& p, size_t k, const std::string& folder) const;
};

// a sweep resolved: its grid, the shared job settings and the output folder
struct SweepPlan {
  Scene base;
  std::vector<SweepAxis> axes;
  std::vector<SweepPoint> points;
  SweepJobs jobs;
  std::string out;
};

// the same sweep command line with `extra` flags instead of the ones that choose what it does
// (--print-jobs, --slurm, --gather, --out): the reference job and the gather job
std::vector<std::string> sweep_args(const SweepCommand& command, const SweepJobs& jobs,
                                    const std::vector<std::string>& extra);
// argv as one shell command line
std::string command_line(const std::vector<std::string>& args);

// sweep.csv from each point's summary.json under `folder`/points; returns the points that did
// not end stable
int write_sweep_csv(const std::vector<SweepAxis>& axes, const std::vector<SweepPoint>& points,
                    const std::string& folder);

// --gather DIR: checks that every point of the plan is in DIR/points/K, ran by chainmail, from
// this very sweep (UsageError naming the point otherwise), then writes DIR/sweep.csv, the plot
// and the sweep's manifest
int gather_sweep(const SweepCommand& command, const SweepPlan& plan);

// --slurm FILE: the submission script (never over a file chainmail did not write)
void write_slurm_script(const SweepCommand& command, const SweepPlan& plan);

}  // namespace chainmail

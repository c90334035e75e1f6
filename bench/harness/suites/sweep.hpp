// Sweeps: error against run time, one independent `chainmail run` per point of a grid of knob
// values, every point measured against one reference run.
#pragma once

#include <string>
#include <vector>

namespace chainmail {

struct SweepCommand {
  std::string scene_file;
  std::vector<std::string> vary;      // KEY=v1,v2,...; "{backend}" in KEY stands for each backend
  std::vector<std::string> backends;  // empty: the scene's own list
  std::vector<std::string> overrides;
  std::string out_dir;  // default results/<scene>/sweep
  bool force = false;   // replace a foreign empty folder at out_dir
  int jobs = 1;
  int threads = 0;  // threads each point steps on; 0: the hardware threads shared by the jobs
  bool print_jobs = false;      // print the reference job, then one `chainmail run` per point; stop
  bool reference_only = false;  // run the reference into the cache and stop (the reference job)
  std::string gather;           // DIR: sweep.csv and the plot from DIR/points/K, run elsewhere
  std::string slurm;            // FILE: write a Slurm submission script there and stop
  std::string executable;       // the chainmail binary that runs each point
  bool progress = true;
  std::string cache_dir;  // "" = the default cache folder, "none" = no cache
};
// threads each point steps on: --threads, else the hardware threads divided among the jobs
int sweep_threads(const SweepCommand& command);
int sweep_command(const SweepCommand& command);

// one --vary axis
struct SweepAxis {
  std::string key;  // as given: "{backend}" stands for each backend
  std::vector<std::string> values;
};

// one point of the grid: one backend's run at one value of each axis
struct SweepPoint {
  std::string backend;
  std::vector<std::string> values;  // one per axis; "" where the axis is another backend's knob
  std::vector<std::string> sets;    // the KEY=VALUE overrides the point adds to the scene
};

// --vary texts (KEY=v1,v2,...) to axes; throws UsageError for a text that is not of that form,
// and when there is none
std::vector<SweepAxis> parse_vary(const std::vector<std::string>& vary);

// every point of the grid: backend by backend in the order given, the first axis varying
// fastest. A key under `backends.` that names another backend does not change this backend's
// run: its value is left out of the point, and the points it would repeat are dropped.
std::vector<SweepPoint> sweep_grid(const std::vector<SweepAxis>& axes,
                                   const std::vector<std::string>& backends);

// the dt of the reference run that every point (and a plain run) is measured against: the
// scene's reference_dt when it gives one (> 0), else the finest of the reference backend's dt in
// the scene and the dts the sweep runs that backend at
double reference_run_dt(double scene_reference_dt, double scene_dt,
                        const std::vector<double>& swept_dts);

}  // namespace chainmail

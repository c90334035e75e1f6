// What `chainmail sweep` is asked: the command's options, read by the sweep itself and by the
// commands that run its points elsewhere (sweep_jobs.hpp).
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

}  // namespace chainmail

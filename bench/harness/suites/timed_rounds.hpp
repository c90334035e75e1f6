// Timing runs taken in rounds: every entry (a backend on a number of threads) runs once a round,
// in order, until each has had its runs, so that a slow spell of a shared machine falls on all of
// them alike instead of on one entry's runs. The scaling table and the bench's timing table both
// measure this way, and both report the median.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bench/harness/run/run.hpp"

namespace chainmail {

struct TimedEntry {
  std::string backend;
  int threads = 1;
  int runs = 1;         // how many times it runs (rounds past this skip it)
  int runs_before = 0;  // runs already taken elsewhere: the progress lines count on from them
};

struct TimedResult {
  std::vector<double> ms_per_step;  // every finished run's, in order
  BackendRun last;                  // the last finished run (dt, steps, verdict, hash, ...)
  bool hashes_agree = true;         // every finished run ended on the same hash
};

// the entries' runs of `scene`, without a reference run or frames kept; `label` names them in the
// progress lines ("bench: <kind> <backend> <label> on N threads (run r of n)"). A Ctrl-C stops
// between runs: the results hold the runs that finished.
std::vector<TimedResult> run_in_rounds(const Scene& scene, const std::vector<TimedEntry>& entries,
                                       const std::string& kind, const std::string& label,
                                       bool progress);

// the entries of one scene, for run_in_rounds over several
struct SceneEntries {
  const Scene* scene = nullptr;
  std::string label;
  std::vector<TimedEntry> entries;
};

// the same over several scenes: each round takes every scene's entries in turn, so that a slow
// spell falls on every scene alike as well (the scaling table's ratios between sizes); a result
// list per scene, in the entries' order
std::vector<std::vector<TimedResult>> run_in_rounds(const std::vector<SceneEntries>& scenes,
                                                    const std::string& kind, bool progress);

// the median of a non-empty list (the upper one of an even count), 0 for an empty one
double median_of(std::vector<double> values);

}  // namespace chainmail

#include "bench/harness/suites/timed_rounds.hpp"

#include <algorithm>
#include <cstdio>

#include "bench/harness/common/interrupt.hpp"

namespace chainmail {

std::vector<TimedResult> run_in_rounds(const Scene& scene, const std::vector<TimedEntry>& entries,
                                       const std::string& kind, const std::string& label,
                                       bool progress) {
  std::vector<TimedResult> results(entries.size());
  int rounds = 0;
  for (const TimedEntry& entry : entries) rounds = std::max(rounds, entry.runs);
  for (int round = 0; round < rounds && !interrupted(); ++round) {
    for (std::size_t k = 0; k < entries.size() && !interrupted(); ++k) {
      const TimedEntry& entry = entries[k];
      if (round >= entry.runs) continue;
      if (progress)
        std::fprintf(stderr, "bench: %s %s %s on %d thread%s (run %d of %d)\n", kind.c_str(),
                     entry.backend.c_str(), label.c_str(), entry.threads,
                     entry.threads == 1 ? "" : "s", entry.runs_before + round + 1,
                     entry.runs_before + entry.runs);
      RunOptions options;
      options.backends = {entry.backend};
      options.progress = false;
      options.reference = kNoReference;
      options.threads = entry.threads;
      SceneRun run = run_scene(scene, options);
      BackendRun& b = run.runs.at(0);
      if (b.steps == 0) continue;
      TimedResult& result = results[k];
      result.ms_per_step.push_back(b.ms_per_step());
      result.hashes_agree =
          result.hashes_agree && (result.ms_per_step.size() == 1 || b.hash == result.last.hash);
      result.last = std::move(b);
    }
  }
  return results;
}

double median_of(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace chainmail

#include "bench/harness/suites/timed_rounds.hpp"

#include <algorithm>
#include <cstdio>

#include "bench/harness/common/interrupt.hpp"

namespace chainmail {

namespace {

// one run of `entry` on `scene`, added to `result`
void run_once(const Scene& scene, const TimedEntry& entry, TimedResult& result) {
  RunOptions options;
  options.backends = {entry.backend};
  options.progress = false;
  options.reference = kNoReference;
  options.threads = entry.threads;
  SceneRun run = run_scene(scene, options);
  BackendRun& b = run.runs.at(0);
  if (b.steps == 0) return;
  result.ms_per_step.push_back(b.ms_per_step());
  result.hashes_agree =
      result.hashes_agree && (result.ms_per_step.size() == 1 || b.hash == result.last.hash);
  result.last = std::move(b);
}

}  // namespace

std::vector<std::vector<TimedResult>> run_in_rounds(const std::vector<SceneEntries>& scenes,
                                                    const std::string& kind, bool progress) {
  std::vector<std::vector<TimedResult>> results;
  int rounds = 0;
  for (const SceneEntries& group : scenes) {
    results.emplace_back(group.entries.size());
    for (const TimedEntry& entry : group.entries) rounds = std::max(rounds, entry.runs);
  }
  for (int round = 0; round < rounds && !interrupted(); ++round) {
    for (std::size_t g = 0; g < scenes.size() && !interrupted(); ++g) {
      const SceneEntries& group = scenes[g];
      for (std::size_t k = 0; k < group.entries.size() && !interrupted(); ++k) {
        const TimedEntry& entry = group.entries[k];
        if (round >= entry.runs) continue;
        if (progress)
          std::fprintf(stderr, "bench: %s %s %s on %d thread%s (run %d of %d)\n", kind.c_str(),
                       entry.backend.c_str(), group.label.c_str(), entry.threads,
                       entry.threads == 1 ? "" : "s", entry.runs_before + round + 1,
                       entry.runs_before + entry.runs);
        run_once(*group.scene, entry, results[g][k]);
      }
    }
  }
  return results;
}

std::vector<TimedResult> run_in_rounds(const Scene& scene, const std::vector<TimedEntry>& entries,
                                       const std::string& kind, const std::string& label,
                                       bool progress) {
  return run_in_rounds({{&scene, label, entries}}, kind, progress).at(0);
}

double median_of(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace chainmail

// Counters the micro-benchmarks of a model's step share: each stage's ms per step over the timed
// steps, and the final state's hash.
#pragma once

#include <cstdint>
#include <string>

#include <benchmark/benchmark.h>

#include "core/frame.hpp"
#include "core/profile.hpp"

namespace chainmail {

// `<stage>_ms`: ms per step of each stage over `steps` timed steps, the profile's growth from
// `before` to `after` (an empty `before`: the whole profile). Returns the stages' seconds summed,
// the time in all only where no stage is nested in another.
inline double add_stage_counters(benchmark::State& bench, const StageProfile& before,
                                 const StageProfile& after, long long steps) {
  double total_s = 0.0;
  for (const auto& [stage, stats] : after.stages()) {
    const auto old = before.stages().find(stage);
    const double seconds =
        stats.seconds - (old == before.stages().end() ? 0.0 : old->second.seconds);
    bench.counters[stage + "_ms"] = 1e3 * seconds / static_cast<double>(steps);
    total_s += seconds;
  }
  return total_s;
}

// `hash48`: the final state hash's low 48 bits (a counter is a double), to compare across runs
inline void add_hash_counter(benchmark::State& bench, const RingFrame& frame) {
  bench.counters["hash48"] = static_cast<double>(frame_hash(frame) & 0xffffffffffffull);
}

}  // namespace chainmail

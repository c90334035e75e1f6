// The plausible step of a 256 x 256 curtain (65,536 rings, self-contact on, default knobs:
// substeps of one sweep under the stretch control) on 1 and 2 threads. The sheet first falls
// for 0.1 s from the layout, untimed, so the timed steps see links taut and rings moving; each
// iteration then times 10 steps, with the lane kernels in AVX2 where the machine has it
// (vector:1, the default) or in the portable lanes (vector:0). Counters: ms per step in all and per
// stage, and the state hash (the same on any thread count, either way).
#include <string>

#include <benchmark/benchmark.h>

#include "bench/micro/stage_counters.hpp"
#include "core/plausible/plausible.hpp"
#include "core/weave.hpp"
#include "scene_file/scene_file.hpp"

namespace {

using namespace chainmail;

void BM_PlausibleLargeCurtain(benchmark::State& bench) {
  const int side = 256;
  const int threads = static_cast<int>(bench.range(0));
  const bool vector = bench.range(1) != 0;
  const Scene scene =
      load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json",
                      {"weave.rows=" + std::to_string(side), "weave.cols=" + std::to_string(side)});
  const Weave weave = make_weave(scene.weave, scene.ring);
  const double dt = 0.004;  // the backend's default
  PlausibleSim sim;
  sim.set_threads(threads);
  sim.set_vector_sweeps(vector);
  sim.reset(scene, weave, PlausibleSettings{});
  for (int s = 0; s < 25; ++s) sim.step(dt);  // settle in: 0.1 s, untimed
  const StageProfile before = sim.profile();
  constexpr int kSteps = 10;
  long long timed = 0;
  long long substeps = 0;  // the substeps the timed steps took (the stretch control may add)
  for (auto _ : bench) {
    for (int s = 0; s < kSteps; ++s) {
      substeps += sim.state().substeps;  // what this step takes
      sim.step(dt);
    }
    timed += kSteps;
  }
  // the stages over the timed steps only: the profile's growth since the settling (no collider:
  // no stage is nested in another, so they sum to the step)
  const double total_s = add_stage_counters(bench, before, sim.profile(), timed);
  bench.counters["ms_per_step"] = 1e3 * total_s / static_cast<double>(timed);
  bench.counters["realtime_factor"] = dt * static_cast<double>(timed) / total_s;
  bench.counters["max_over_extension"] = sim.max_over_extension();
  bench.counters["substeps_per_step"] = static_cast<double>(substeps) / static_cast<double>(timed);
  RingFrame frame;
  sim.frame(frame);
  add_hash_counter(bench, frame);  // equal across the thread counts
}

}  // namespace

BENCHMARK(BM_PlausibleLargeCurtain)
    ->ArgNames({"threads", "vector"})
    ->ArgsProduct({{1, 2}, {1, 0}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3)
    ->UseRealTime();

// The torus_xpbd step of the bench's 16 x 16 curtain (self-contact on, default knobs: dt 5 ms, 25
// substeps, 8 velocity passes) on 1 and 2 threads. The sheet first hangs for 0.1 s from the
// layout, untimed; each iteration then times 20 steps. Counters: ms per step (wall), the stages'
// ms per step (`self_contact` is part of `contacts`), and the state hash (the same on any thread
// count).
#include <chrono>
#include <string>

#include <benchmark/benchmark.h>

#include "bench/micro/stage_counters.hpp"
#include "core/torus_xpbd/torus_xpbd.hpp"
#include "core/weave.hpp"
#include "scene_file/scene_file.hpp"

namespace {

using namespace chainmail;

void BM_TorusXpbdCurtain(benchmark::State& bench) {
  const int threads = static_cast<int>(bench.range(0));
  const Scene scene = load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json",
                                      {"weave.rows=16", "weave.cols=16"});
  const Weave weave = make_weave(scene.weave, scene.ring);
  const double dt = 0.005;  // the backend's default
  TorusXpbdSim sim;
  sim.set_threads(threads);
  sim.reset(scene, weave, TorusXpbdSettings{});
  for (int s = 0; s < 20; ++s) sim.step(dt);  // settle in: 0.1 s, untimed
  const StageProfile before = sim.profile();
  constexpr int kSteps = 20;
  long long timed = 0;
  double wall_s = 0.0;
  for (auto _ : bench) {
    const auto start = std::chrono::steady_clock::now();
    for (int s = 0; s < kSteps; ++s) sim.step(dt);
    wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    timed += kSteps;
  }
  // the stages over the timed steps only: the profile's growth since the settling
  add_stage_counters(bench, before, sim.profile(), timed);
  bench.counters["ms_per_step"] = 1e3 * wall_s / static_cast<double>(timed);
  bench.counters["ms_per_simulated_s"] = wall_s / (dt * static_cast<double>(timed)) * 1e3;
  RingFrame frame;
  sim.frame(frame);
  add_hash_counter(bench, frame);  // equal across the thread counts
}

}  // namespace

BENCHMARK(BM_TorusXpbdCurtain)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3)
    ->UseRealTime();

// Milliseconds per step of the plausible model on the committed `curtain` scene at the paper's
// 30x30 and at 100x100, self-contact on, default knobs. Each iteration runs one simulated second
// from rest (the swing after release is the expensive part for self-contact), and the counters
// give the per-stage split so a regression can be traced to its phase.
#include <chrono>
#include <string>

#include <benchmark/benchmark.h>

#include "bench/micro/stage_counters.hpp"
#include "core/plausible/plausible.hpp"
#include "core/weave.hpp"
#include "scene_file/scene_file.hpp"

namespace {

using namespace chainmail;

void BM_PlausibleCurtain(benchmark::State& bench) {
  const int side = static_cast<int>(bench.range(0));
  const Scene scene =
      load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json",
                      {"weave.rows=" + std::to_string(side), "weave.cols=" + std::to_string(side)});
  const Weave weave = make_weave(scene.weave, scene.ring);
  const double dt = 0.004;  // the backend's default
  const int steps = static_cast<int>(1.0 / dt);
  PlausibleSim sim;
  double total_s = 0.0;  // the steps alone, without the reset
  for (auto _ : bench) {
    sim.reset(scene, weave, PlausibleSettings{});
    const auto start = std::chrono::steady_clock::now();
    for (int s = 0; s < steps; ++s) sim.step(dt);
    total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  // one iteration (see below): the profile covers exactly the timed steps. Stages can nest (the
  // colliders inside integrate, where a ring starts a step inside one): the total is timed, not
  // summed from them
  add_stage_counters(bench, StageProfile{}, sim.profile(), steps);
  bench.counters["ms_per_step"] = 1e3 * total_s / steps;
  bench.counters["realtime_factor"] = dt * steps / total_s;
  bench.counters["contact_rebuilds"] = static_cast<double>(sim.state().contact_rebuilds);
}

}  // namespace

BENCHMARK(BM_PlausibleCurtain)->Arg(30)->Arg(100)->Unit(benchmark::kMillisecond)->Iterations(1);

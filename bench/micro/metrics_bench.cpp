// Milliseconds per sample: the harness's metrics (core/metrics: stretch, exact torus depths of
// linked and nearby pairs, broken and false links) on a hanging 4-in-1 curtain of side x side
// rings, the plausible model's frame after 0.2 s (links taut, rows drawn together); and the
// plausible model's frame itself on the bench's table cloth after 1 s, where the rings the centre
// frames leave unlinked in the folds are turned to keep their links (keep_links). On large sheets
// a sample costs more than a step, so a run's wall time follows it.
#include <string>

#include <benchmark/benchmark.h>

#include "core/metrics.hpp"
#include "core/plausible/plausible.hpp"
#include "core/weave.hpp"
#include "scene_file/scene_file.hpp"

namespace {

using namespace chainmail;

void BM_MeasureCurtain(benchmark::State& bench) {
  const int side = static_cast<int>(bench.range(0));
  const Scene scene =
      load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json",
                      {"weave.rows=" + std::to_string(side), "weave.cols=" + std::to_string(side)});
  const Weave weave = make_weave(scene.weave, scene.ring);
  PlausibleSim sim;
  sim.reset(scene, weave, PlausibleSettings{});
  for (int s = 0; s < 50; ++s) sim.step(0.004);
  RingFrame frame;
  sim.frame(frame);
  Metrics m;
  for (auto _ : bench) {
    m = measure(frame, weave, scene, MetricOptions{});
    benchmark::DoNotOptimize(m);
  }
  bench.counters["penetrating_linked"] = static_cast<double>(m.penetrating_linked);
  bench.counters["penetrating_other"] = static_cast<double>(m.penetrating_other);
}

void BM_FrameTableCloth(benchmark::State& bench) {
  const Scene scene = load_scene_file(
      CHAINMAIL_SOURCE_DIR "/bench/scenes/table_cloth.json",
      {"weave.rows=16", "weave.cols=16", "colliders.0.radius=0.03", "support.radius=0.03"});
  const Weave weave = make_weave(scene.weave, scene.ring);
  PlausibleSim sim;
  sim.reset(scene, weave, PlausibleSettings{});
  for (int s = 0; s < 250; ++s) sim.step(0.004);
  RingFrame frame;
  for (auto _ : bench) {
    sim.frame(frame);  // the orientations are the state's; each frame turns its own copy
    benchmark::DoNotOptimize(frame.orientation.data());
  }
}

}  // namespace

BENCHMARK(BM_MeasureCurtain)->Arg(32)->Arg(128)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrameTableCloth)->Unit(benchmark::kMillisecond);

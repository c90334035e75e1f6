// Milliseconds per frame of the shared renderer at 1280x720: a 30x30 and a 100x100 4-in-1 sheet
// at rest, framed by the automatic camera, with and without level of detail (without: every ring
// the finest mesh; with: the small ones ray-cast), 4x MSAA and none.
// Each render() includes the instance upload, the draws, the MSAA resolve and the read-back.
#include <map>
#include <memory>
#include <string>
#include <tuple>

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include "core/weave.hpp"
#include "render/renderer.hpp"
#include "scene_file/scene_file.hpp"

namespace {

using namespace chainmail;

struct Sheet {
  Scene scene;
  Weave weave;
  RingFrame frame;
};

const Sheet& sheet(int side) {
  static std::map<int, Sheet> sheets;
  auto [it, inserted] = sheets.try_emplace(side);
  if (inserted) {
    Sheet& s = it->second;
    s.scene = scene_from_json(
        {{"name", "bench"},
         {"weave", {{"type", "4in1"}, {"rows", side}, {"cols", side}}},
         {"colliders", nlohmann::json::array({{{"type", "plane"}, {"point", {0.0, -0.01, 0.0}}}})},
         {"duration", 1.0}},
        "render_bench");
    s.weave = make_weave(s.scene.weave, s.scene.ring);
    s.frame.resize(s.weave.size());
    s.frame.position = s.weave.rest_position;
    s.frame.orientation = s.weave.rest_orientation;
    s.frame.velocity.setZero();
  }
  return it->second;
}

// args: sheet side (rings), lod (0/1), MSAA samples
void BM_RenderSheet(benchmark::State& state) {
  const int side = static_cast<int>(state.range(0));
  render::RenderSettings settings;
  settings.width = 1280;
  settings.height = 720;
  settings.lod = state.range(1) != 0;
  settings.samples = static_cast<int>(state.range(2));
  settings.shader_dir = std::string(CHAINMAIL_SOURCE_DIR) + "/shaders";
  std::unique_ptr<render::Renderer> renderer;
  try {
    renderer = render::Renderer::create(settings);
  } catch (const render::RenderError& error) {
    state.SkipWithError(error.what());
    return;
  }
  const Sheet& s = sheet(side);
  const std::vector<render::Panel> panels = {{"bench", &s.frame}};
  renderer->render(s.scene, s.weave, panels);  // first frame compiles shader variants
  for (auto _ : state) {
    render::Image image = renderer->render(s.scene, s.weave, panels);
    benchmark::DoNotOptimize(image.rgba.data());
  }
  const render::FrameStats& stats = renderer->last_stats();
  state.counters["rings"] = stats.instances;
  for (int level = 0; level < render::kLodLevels; ++level) {
    const bool raycast = level == render::kMeshLevels;
    state.counters[raycast ? "raycast" : "mesh" + std::to_string(level)] = stats.per_lod[level];
  }
  state.SetLabel(renderer->context_name());
}

BENCHMARK(BM_RenderSheet)
    ->ArgNames({"side", "lod", "msaa"})
    ->ArgsProduct({{30, 100}, {1, 0}, {4, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);

}  // namespace

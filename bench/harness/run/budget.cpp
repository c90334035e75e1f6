#include "bench/harness/run/budget.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "backends/backend.hpp"

namespace chainmail {
namespace {

std::string gigabytes(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g GB", bytes / 1e9);
  return text;
}

}  // namespace

long long ring_count(const Scene& scene) {
  const long long rows = scene.weave.type == WeaveType::chain ? 1 : scene.weave.rows;
  return rows * scene.weave.cols;
}

long long step_count(const Scene& scene, const std::string& backend) {
  const BackendInfo* info = find_backend(backend);
  if (!info) return 0;
  const double dt = resolve_knobs(scene, *info).at("dt");
  return std::max(1LL, std::llround(std::min(scene.duration / dt, 9e18)));
}

double estimate_seconds(const Scene& scene, const std::string& backend) {
  const BackendInfo* info = find_backend(backend);
  if (!info) return 0.0;
  // the step itself, and the metrics of each sample (about a microsecond per ring)
  const double samples = scene.duration / scene.sample_interval + 1.0;
  return 1e-6 * static_cast<double>(ring_count(scene)) *
         (info->cost_us_per_ring_step * static_cast<double>(step_count(scene, backend)) + samples);
}

Estimate estimate_run(const Scene& scene, const std::vector<std::string>& backends,
                      double frame_bytes_per_ring_sample) {
  Estimate e;
  e.rings = ring_count(scene);
  // the weave, one frame and the metric work arrays, whatever the backend
  const double shared = 600.0 * static_cast<double>(e.rings);
  const double samples = scene.duration / scene.sample_interval + 1.0;
  double slowest = -1.0;
  for (const auto& name : backends) {
    const BackendInfo* info = find_backend(name);
    if (!info) continue;
    const double memory = shared + info->bytes_per_ring * static_cast<double>(e.rings);
    if (memory > e.memory_bytes) e.memory_bytes = memory, e.largest = name;
    const double seconds = estimate_seconds(scene, name);
    e.wall_seconds += seconds;
    if (seconds > slowest)
      slowest = seconds, e.slowest = name, e.slowest_steps = step_count(scene, name);
    e.output_bytes += frame_bytes_per_ring_sample * static_cast<double>(e.rings) * samples;
  }
  return e;
}

void check_budget(const Scene& scene, const Estimate& e, const Budget& budget) {
  const std::string file = scene.file + ": key ";
  char rings[96];
  std::snprintf(rings, sizeof rings, "%lld rings", e.rings);
  if (e.memory_bytes > budget.max_memory_gb * 1e9) {
    throw SceneError(file + "'weave': " + rings + " need an estimated " +
                     gigabytes(e.memory_bytes) + " of memory in " + e.largest + ", over the " +
                     gigabytes(budget.max_memory_gb * 1e9) + " budget (--max-memory GB raises it)");
  }
  if (e.wall_seconds > budget.max_hours * 3600.0) {
    char steps[160];
    std::snprintf(steps, sizeof steps, "%lld steps of %lld rings in %s", e.slowest_steps, e.rings,
                  e.slowest.c_str());
    throw SceneError(file + "'duration': " + steps + " and the rest take an estimated " +
                     human_duration(e.wall_seconds) + ", over the " +
                     human_duration(budget.max_hours * 3600.0) +
                     " budget (--max-hours H raises it)");
  }
  if (e.output_bytes > budget.max_output_gb * 1e9) {
    throw SceneError(file + "'sample_interval': the frames of " + rings +
                     " at every sample take an estimated " + gigabytes(e.output_bytes) +
                     " on disk, over the " + gigabytes(budget.max_output_gb * 1e9) +
                     " budget (a longer sample_interval, or --max-output GB)");
  }
}

std::string human_duration(double seconds) {
  char text[48];
  if (!std::isfinite(seconds) || seconds > 1e12) return "forever";
  if (seconds < 90.0)
    std::snprintf(text, sizeof text, "%.0f s", seconds);
  else if (seconds < 5400.0)
    std::snprintf(text, sizeof text, "%.1f min", seconds / 60.0);
  else
    std::snprintf(text, sizeof text, "%.1f h", seconds / 3600.0);
  return text;
}

}  // namespace chainmail

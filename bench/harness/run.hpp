// Running one scene through one or more backends, and everything a run measures.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "backends/backend.hpp"
#include "core/frame.hpp"
#include "core/metrics.hpp"
#include "core/scene.hpp"
#include "core/weave.hpp"

namespace chainmail {

struct RunOptions {
  std::vector<std::string> backends;  // empty: the scene's backends object, else every backend
  bool keep_frames = true;            // keep the sampled frames (rendering, frame files, drape_rms)
  bool progress = true;               // progress line on stderr for runs longer than a second
  double max_wall_seconds = 0.0;      // watchdog per backend run; 0 = none
  std::string cache_dir;              // reference runs cached here by scene hash; empty = no cache
  bool other_pair_metrics = true;  // penetrating_other / false_links (broad phase over all rings)
};

struct Sample {
  double t = 0.0;
  Metrics metrics;
  double step_wall_ms = 0.0;  // mean wall time of the steps since the previous sample
};

struct BackendRun {
  std::string name;
  Knobs knobs;
  double dt = 0.0;
  long long steps = 0;
  double wall_s = 0.0;  // time inside step() only
  bool stable = true;
  std::string verdict = "stable";  // or the instability that ended the run
  std::uint64_t hash = 0;          // frame_hash of the final frame
  std::vector<Sample> samples;
  std::vector<RingFrame> frames;  // one per sample when keep_frames
  RingFrame final_frame;
  std::map<std::string, StageStats> stages;
  std::optional<double> catenary_error;  // chains pinned at both ends: sag against the catenary

  double ms_per_step() const { return steps ? 1e3 * wall_s / steps : 0.0; }
  // simulated seconds per wall second
  double realtime_factor() const { return wall_s > 0 ? steps * dt / wall_s : 0.0; }
  const Metrics& final_metrics() const { return samples.back().metrics; }
};

struct SceneRun {
  Scene scene;
  Weave weave;
  std::vector<BackendRun> runs;
  std::optional<std::string> reference_note;  // where drape_rms came from
  bool all_stable() const;
};

// the backends a run uses: explicit list ("all" = every backend), else those the scene configures
std::vector<std::string> select_backends(const Scene& scene,
                                         const std::vector<std::string>& requested);

// one backend over the scene's duration; never throws for an unstable simulation
BackendRun run_backend(const Scene& scene, const Weave& weave, const std::string& backend,
                       const RunOptions& options);

// every selected backend, then drape_rms against the reference run
SceneRun run_scene(const Scene& scene, const RunOptions& options);

// the frames of the reference run (scene.reference backend), from the cache when present
std::vector<RingFrame> reference_frames(const Scene& scene, const Weave& weave,
                                        const RunOptions& options, const SceneRun* already);

// hash of what determines a run's result (the resolved scene without output-only keys)
std::string scene_content_hash(const Scene& scene, const std::string& backend);

}  // namespace chainmail

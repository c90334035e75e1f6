// Running one scene through one or more backends, and everything a run measures.
// Samples are streamed: each sample's metric row and frame go to disk as they are taken, so the
// memory a run needs does not grow with its duration.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "backends/backend.hpp"
#include "bench/harness/run/verdict.hpp"
#include "core/frame.hpp"
#include "core/metrics.hpp"
#include "core/scene.hpp"
#include "core/weave.hpp"

namespace chainmail {

// a ring run is settled when its kinetic energy at the end is below this fraction of the energy
// the run was given (potential energy released plus the initial kinetic energy)
inline constexpr double kSettledEnergyFraction = 0.01;
// linked rings cannot be farther apart than the inner diameter: above 1 + this is impossible
inline constexpr double kOverstretchTolerance = 0.005;

struct RunOptions {
  std::vector<std::string> backends;  // empty: the scene's backends object, else every backend
  bool progress = true;               // progress line on stderr for runs longer than a second
  double max_wall_seconds = 0.0;      // watchdog per backend run; 0 = none
  std::string cache_dir;              // reference runs cached here by content hash; "" = none
  std::string reference;              // backend for drape_rms; "" = the scene's, "none" = none
  bool other_pair_metrics = true;  // penetrating_other / false_links (broad phase over all rings)
  // where a run streams its samples (a command's staging folder); "" = nothing written
  std::string folder;
  bool frame_csv = false;    // frames/<backend>/<NNNNN>.csv under folder
  bool keep_stream = false;  // every backend's frames in .streams/ under folder (for rendering)
  int threads = 1;           // threads each backend steps on (Backend::set_threads)
};

struct Sample {
  double t = 0.0;
  Metrics metrics;
  double step_wall_ms = 0.0;  // mean wall time of the steps since the previous sample
};

// called for every sample as it is taken (the frame is finite unless the verdict says otherwise)
using SampleHook = std::function<void(const RingFrame& frame, Sample& sample)>;

struct BackendRun {
  std::string name;
  Knobs knobs;
  double dt = 0.0;
  long long steps = 0;
  double wall_s = 0.0;                // time inside step() only
  bool stable = true;                 // verdict == Verdict::stable
  Verdict verdict = Verdict::stable;  // or the instability or stop that ended the run
  std::uint64_t hash = 0;             // frame_hash of the final frame
  long long samples = 0;              // samples taken
  std::optional<Sample> last;         // the last sample (absent when the run never started)
  RingFrame final_frame;
  std::map<std::string, StageStats> stages;
  ResidualStats residual;                // steps = 0: the backend reports none
  std::optional<double> catenary_error;  // chains pinned at both ends: sag against the catenary
  double peak_stretch = 0.0;             // largest max_stretch over every sample
  std::optional<bool> settled;           // absent when the run did not end stable
  std::optional<bool> overstretched;     // ring weaves only: peak_stretch above 1 + tolerance
  std::string stream;                    // file of its sampled frames ("" when none was kept)

  double ms_per_step() const { return steps ? 1e3 * wall_s / steps : 0.0; }
  // simulated seconds per wall second
  double realtime_factor() const { return wall_s > 0 ? steps * dt / wall_s : 0.0; }
  bool started() const { return last.has_value(); }
  const Metrics& final_metrics() const { return last->metrics; }
};

struct SceneRun {
  Scene scene;
  Weave weave;
  std::vector<BackendRun> runs;
  std::optional<std::string> reference_note;  // where drape_rms came from
  bool interrupted = false;                   // a signal stopped it: some runs did not finish
  int threads = 1;                            // threads each backend stepped on
  bool all_stable() const;
};

// --backends all: every backend built into this binary
inline constexpr const char* kAllBackends = "all";
// --reference none: no reference run
inline constexpr const char* kNoReference = "none";

// the backends a run uses: an explicit list ("all" = every built backend; a name not built into
// this binary is a UsageError), else those the scene configures that are built (the others
// skipped with a note on stderr), else every built backend
std::vector<std::string> select_backends(const Scene& scene,
                                         const std::vector<std::string>& requested);

// one backend over the scene's duration; never throws for an unstable simulation. Stops early on
// a signal (verdict interrupted). `hook` sees every sample as it is taken.
BackendRun run_backend(const Scene& scene, const Weave& weave, const std::string& backend,
                       const RunOptions& options, const SampleHook& hook = {});
// the same for a backend given by its registry entry (a test's own backend, too)
BackendRun run_backend(const Scene& scene, const Weave& weave, const BackendInfo& info,
                       const RunOptions& options, const SampleHook& hook = {});

// every selected backend, drape_rms against the reference run taken as the samples come
SceneRun run_scene(const Scene& scene, const RunOptions& options);

// the reference backend of a run ("" when none: --reference none, or a backend not built into
// this binary)
std::string reference_backend(const Scene& scene, const RunOptions& options);
// the scene the reference run uses (its reference_dt applied)
Scene reference_scene(const Scene& scene, const std::string& reference);
// the cache file of a reference run ("" without a cache folder)
std::string reference_cache_path(const Scene& scene, const std::string& reference,
                                 const std::string& cache_dir);
// make sure the reference run is in the cache: run it unless a valid file is there. False when it
// cannot be (unstable, not built into this binary, or the cache cannot be written: then each user
// runs it again).
bool ensure_reference_cached(const Scene& scene, const std::string& reference,
                             const RunOptions& options);

// hash of what determines a run's result (the resolved scene without output-only keys)
std::string scene_content_hash(const Scene& scene, const std::string& backend);

}  // namespace chainmail

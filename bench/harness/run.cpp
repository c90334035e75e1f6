#include "bench/harness/run.hpp"

#include "bench/harness/suites.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace chainmail {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// total mechanical energy relative to the origin: kinetic + potential in the scene's gravity
double mechanical_energy(const RingFrame& frame, const Metrics& metrics, const Scene& scene,
                         const std::vector<double>& mass) {
  double potential = 0.0;
  for (int i = 0; i < frame.size(); ++i)
    potential -= mass[i] * scene.gravity.dot(frame.position.col(i));
  return metrics.kinetic_energy + potential;
}

// energy scale of the scene: every ring falling across the rest layout's extent once
double energy_scale(const Scene& scene, const Weave& weave) {
  const Vec3 extent =
      weave.rest_position.rowwise().maxCoeff() - weave.rest_position.rowwise().minCoeff();
  const double size = std::max(extent.norm(), scene.ring.centre_radius);
  double total = 0.0;
  for (double m : ring_masses(scene, weave)) total += m;
  const double speed = scene.initial_velocity.norm();
  return total * (std::max(scene.gravity.norm(), 1.0) * size + 0.5 * speed * speed);
}

std::string hex(std::uint64_t value) {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(value));
  return buffer;
}

}  // namespace

bool SceneRun::all_stable() const {
  for (const auto& run : runs) {
    if (!run.stable) return false;
  }
  return true;
}

std::vector<std::string> select_backends(const Scene& scene,
                                         const std::vector<std::string>& requested) {
  std::vector<std::string> names;
  const bool all = requested.size() == 1 && requested[0] == "all";
  if (all || requested.empty()) {
    for (const auto& info : backend_registry()) {
      if (all || scene.backends.empty() || scene.backends.contains(info.name))
        names.push_back(info.name);
    }
    return names;
  }
  for (const auto& name : requested) {
    if (!find_backend(name)) {
      std::string known;
      for (const auto& b : backend_registry()) known += (known.empty() ? "" : ", ") + b.name;
      throw SceneError("--backends: unknown backend '" + name + "' (known: " + known + ", all)");
    }
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  return names;
}

BackendRun run_backend(const Scene& scene, const Weave& weave, const std::string& name,
                       const RunOptions& options) {
  const BackendInfo* info = find_backend(name);
  if (!info) throw SceneError("unknown backend '" + name + "'");
  BackendRun run;
  run.name = name;
  run.knobs = resolve_knobs(scene, *info);
  run.dt = run.knobs.at("dt");

  std::unique_ptr<Backend> backend = info->create();
  backend->reset(scene, weave, run.knobs);

  const long long total_steps = std::max(1LL, std::llround(scene.duration / run.dt));
  const long long steps_per_sample = std::max(1LL, std::llround(scene.sample_interval / run.dt));
  MetricOptions metric_options;
  metric_options.other_pairs = options.other_pair_metrics;
  const double scale = energy_scale(scene, weave);
  const std::vector<double> masses = ring_masses(scene, weave);

  RingFrame frame;
  double energy_start = 0.0;
  double interval_wall = 0.0;
  long long interval_steps = 0;
  const auto started = Clock::now();
  auto last_progress = started;
  bool progress_shown = false;
  const bool terminal = ::isatty(2);

  // sample: metrics of the current frame, then the stability checks on them
  auto sample = [&](long long step) {
    backend->frame(frame);
    Sample s;
    s.t = frame.t;
    s.metrics = measure(frame, weave, scene, metric_options);
    s.step_wall_ms = interval_steps ? 1e3 * interval_wall / interval_steps : 0.0;
    interval_wall = 0.0, interval_steps = 0;
    run.samples.push_back(s);
    if (options.keep_frames) run.frames.push_back(frame);

    const Metrics& m = s.metrics;
    if (m.non_finite > 0) {
      run.stable = false, run.verdict = "non_finite";
    } else if (m.max_speed > scene.stability.max_speed) {
      run.stable = false, run.verdict = "max_speed";
    } else if (scene.stability.links_must_hold && m.max_stretch > scene.stability.max_stretch) {
      // torn: farther apart than linked rings can be. (broken_links, the linking test on the
      // emitted orientations, is reported but not a verdict: a particle model's orientations are
      // derived, so its rings can look unlinked while the model holds them together.)
      run.stable = false, run.verdict = "torn_links";
    } else {
      const double energy = mechanical_energy(frame, m, scene, masses);
      if (step == 0) energy_start = energy;
      if (energy - energy_start > (scene.stability.energy_growth - 1.0) * scale) {
        run.stable = false, run.verdict = "energy_growth";
      }
    }
    return run.stable;
  };

  bool keep_going = sample(0);
  for (long long step = 1; keep_going && step <= total_steps; ++step) {
    // step: the only thing timed
    const auto before = Clock::now();
    backend->step(run.dt);
    const double wall = seconds_since(before);
    run.wall_s += wall, interval_wall += wall;
    ++interval_steps, ++run.steps;

    if (step % steps_per_sample == 0 || step == total_steps) keep_going = sample(step);

    // watchdog and progress, by wall clock
    const double elapsed = seconds_since(started);
    if (options.max_wall_seconds > 0.0 && elapsed > options.max_wall_seconds &&
        step < total_steps) {
      run.stable = false;
      run.verdict = "watchdog";
      if (run.samples.back().t < run.dt * step) sample(step);
      break;
    }
    // the first line after a second, then every second on a terminal, every ten in a log
    if (options.progress &&
        seconds_since(last_progress) > (terminal || !progress_shown ? 1.0 : 10.0)) {
      last_progress = Clock::now();
      progress_shown = true;
      std::fprintf(stderr, "%s  %-10s t = %7.3f / %.3f s  %8.3f ms/step%s", terminal ? "\r" : "",
                   name.c_str(), step * run.dt, scene.duration, run.ms_per_step(),
                   terminal ? "  " : "\n");
    }
  }
  if (progress_shown) {
    std::fprintf(stderr, "%s  %-10s t = %7.3f / %.3f s  %8.3f ms/step  %s\n", terminal ? "\r" : "",
                 name.c_str(), run.steps * run.dt, scene.duration, run.ms_per_step(),
                 run.verdict.c_str());
  }

  backend->frame(run.final_frame);
  run.hash = frame_hash(run.final_frame);
  run.stages = backend->profile().stages();
  return run;
}

std::string scene_content_hash(const Scene& scene, const std::string& backend) {
  nlohmann::json key = scene.resolved;
  key.erase("output");
  key.erase("camera");
  key.erase("description");
  key.erase("reference_dt");
  const BackendInfo* info = find_backend(backend);
  nlohmann::json knobs = nlohmann::json::object();
  if (info) {
    for (const auto& [k, v] : resolve_knobs(scene, *info)) knobs[k] = v;
  }
  key["backends"] = {{backend, knobs}};
  const std::string text = key.dump();
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char ch : text) h = (h ^ ch) * 0x100000001b3ull;
  return hex(h);
}

namespace {

// reference frame cache: magic, frame count, ring count, then per frame t and positions
bool load_cached(const std::string& path, std::vector<RingFrame>& frames, int rings) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  char magic[8];
  long long count = 0, n = 0;
  in.read(magic, 8);
  in.read(reinterpret_cast<char*>(&count), sizeof count);
  in.read(reinterpret_cast<char*>(&n), sizeof n);
  if (!in || std::string(magic, 8) != "CMREF001" || n != rings || count <= 0) return false;
  frames.resize(count);
  for (auto& f : frames) {
    f.resize(rings);
    in.read(reinterpret_cast<char*>(&f.t), sizeof f.t);
    in.read(reinterpret_cast<char*>(f.position.data()), sizeof(double) * 3 * rings);
    f.orientation.setZero();
    f.velocity.setZero();
  }
  return static_cast<bool>(in);
}

void store_cached(const std::string& path, const std::vector<RingFrame>& frames) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    const long long count = static_cast<long long>(frames.size());
    const long long n = frames.empty() ? 0 : frames[0].size();
    out.write("CMREF001", 8);
    out.write(reinterpret_cast<const char*>(&count), sizeof count);
    out.write(reinterpret_cast<const char*>(&n), sizeof n);
    for (const auto& f : frames) {
      out.write(reinterpret_cast<const char*>(&f.t), sizeof f.t);
      out.write(reinterpret_cast<const char*>(f.position.data()), sizeof(double) * 3 * n);
    }
    if (!out) return;  // a cache that cannot be written is only a missed speed-up
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
}

const RingFrame& nearest(const std::vector<RingFrame>& frames, double t) {
  size_t best = 0;
  for (size_t k = 1; k < frames.size(); ++k) {
    if (std::abs(frames[k].t - t) < std::abs(frames[best].t - t)) best = k;
  }
  return frames[best];
}

}  // namespace

std::vector<RingFrame> reference_frames(const Scene& scene, const Weave& weave,
                                        const RunOptions& options, const SceneRun* already) {
  // the reference run: the reference backend at reference_dt (default: its dt in this scene)
  Scene reference_scene = scene;
  if (scene.reference_dt > 0.0) {
    nlohmann::json doc = scene.resolved;
    doc["backends"][scene.reference]["dt"] = scene.reference_dt;
    reference_scene = scene_from_json(doc, scene.file);
  }
  const double dt = resolve_knobs(reference_scene, *find_backend(scene.reference)).at("dt");
  // a run of the same backend at the same dt in this very invocation is the reference
  if (already) {
    for (const auto& run : already->runs) {
      if (run.name == scene.reference && run.dt == dt && !run.frames.empty()) {
        return run.stable ? run.frames : std::vector<RingFrame>{};
      }
    }
  }
  const std::string path = options.cache_dir.empty()
                               ? ""
                               : options.cache_dir + "/" + scene.name + "-" + scene.reference +
                                     "-" + scene_content_hash(reference_scene, scene.reference) +
                                     ".bin";
  std::vector<RingFrame> frames;
  if (!path.empty() && load_cached(path, frames, weave.size())) return frames;
  RunOptions quiet = options;
  quiet.keep_frames = true;
  quiet.other_pair_metrics = false;
  if (options.progress) std::fprintf(stderr, "  reference run: %s\n", scene.reference.c_str());
  BackendRun run = run_backend(reference_scene, weave, scene.reference, quiet);
  if (!run.stable) return {};
  if (!path.empty()) store_cached(path, run.frames);
  return run.frames;
}

SceneRun run_scene(const Scene& scene, const RunOptions& options) {
  SceneRun result;
  result.scene = scene;
  result.weave = make_weave(scene.weave, scene.ring);
  validate_backend_knobs(scene);
  const std::vector<std::string> names = select_backends(scene, options.backends);
  for (const auto& name : names) {
    if (options.progress) std::fprintf(stderr, "%s: %s\n", scene.name.c_str(), name.c_str());
    result.runs.push_back(run_backend(scene, result.weave, name, options));
    BackendRun& run = result.runs.back();
    if (run.stable) run.catenary_error = catenary_error(scene, result.weave, run.final_frame);
  }

  // drape_rms: every sample against the reference frame nearest in time
  RunOptions reference_options = options;
  const std::vector<RingFrame> reference =
      reference_frames(scene, result.weave, reference_options, &result);
  if (reference.empty()) {
    result.reference_note = "no stable reference run (" + scene.reference + "): drape_rms absent";
    return result;
  }
  result.reference_note = "drape_rms against " + scene.reference;
  for (auto& run : result.runs) {
    for (size_t k = 0; k < run.samples.size() && k < run.frames.size(); ++k) {
      if (run.samples[k].metrics.non_finite > 0) continue;
      run.samples[k].metrics.drape_rms =
          drape_rms(run.frames[k], nearest(reference, run.frames[k].t));
    }
  }
  return result;
}

}  // namespace chainmail

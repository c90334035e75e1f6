#include "bench/harness/run.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "bench/harness/budget.hpp"
#include "bench/harness/frame_stream.hpp"
#include "bench/harness/interrupt.hpp"
#include "bench/harness/output.hpp"
#include "bench/harness/suites.hpp"
#include "bench/harness/version.hpp"

namespace chainmail {
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// potential energy in the scene's gravity, relative to the origin
double potential_energy(const RingFrame& frame, const Scene& scene,
                        const std::vector<double>& mass) {
  double potential = 0.0;
  for (int i = 0; i < frame.size(); ++i)
    potential -= mass[i] * scene.gravity.dot(frame.position.col(i));
  return potential;
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

// the verdict of one sample's metrics ("" while stable)
std::string verdict_of(const Metrics& m, const Scene& scene, double energy_growth, double scale) {
  if (m.non_finite > 0) return "non_finite";
  if (m.max_speed > scene.stability.max_speed) return "max_speed";
  // torn: farther apart than linked rings can be. (broken_links, the linking test on the emitted
  // orientations, is reported but not a verdict: a particle model's orientations are derived, so
  // its rings can look unlinked while the model holds them together.)
  if (scene.stability.links_must_hold && m.max_stretch > scene.stability.max_stretch)
    return "torn_links";
  if (energy_growth > (scene.stability.energy_growth - 1.0) * scale) return "energy_growth";
  return "";
}

// one progress line: the first after a second, then every second on a terminal, every ten in a log
class Progress {
 public:
  Progress(bool enabled, std::string name, double duration)
      : enabled_(enabled), name_(std::move(name)), duration_(duration), terminal_(::isatty(2)) {}
  void update(double t, double ms_per_step) {
    if (!enabled_ || seconds_since(last_) <= (terminal_ || !shown_ ? 1.0 : 10.0)) return;
    last_ = Clock::now();
    shown_ = true;
    const double elapsed = seconds_since(started_);
    const double eta = t > 0.0 ? elapsed * (duration_ - t) / t : 0.0;
    std::fprintf(stderr, "%s  %-10s t = %7.3f / %.3f s  %8.3f ms/step  ETA %s%s",
                 terminal_ ? "\r" : "", name_.c_str(), t, duration_, ms_per_step,
                 human_duration(eta).c_str(), terminal_ ? "    " : "\n");
  }
  void finish(double t, double ms_per_step, const std::string& verdict) {
    if (!shown_) return;
    std::fprintf(stderr, "%s  %-10s t = %7.3f / %.3f s  %8.3f ms/step  %s%s\n",
                 terminal_ ? "\r" : "", name_.c_str(), t, duration_, ms_per_step, verdict.c_str(),
                 terminal_ ? "            " : "");
  }

 private:
  bool enabled_;
  std::string name_;
  double duration_;
  bool terminal_;
  bool shown_ = false;
  Clock::time_point started_ = Clock::now(), last_ = Clock::now();
};

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
  std::string known;
  for (const auto& b : backend_registry()) known += (known.empty() ? "" : ", ") + b.name;
  for (const auto& name : requested) {
    if (name.empty())
      throw SceneError("--backends: an empty name in the list (known: " + known + ", all)");
    if (!find_backend(name)) {
      throw SceneError("--backends: unknown backend '" + name + "' (known: " + known + ", all)");
    }
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  return names;
}

BackendRun run_backend(const Scene& scene, const Weave& weave, const std::string& name,
                       const RunOptions& options, const SampleHook& hook) {
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
  double energy_start = 0.0, potential_start = 0.0, kinetic_start = 0.0;
  double interval_wall = 0.0;
  long long interval_steps = 0;
  const auto started = Clock::now();
  Progress progress(options.progress, name, scene.duration);

  // sample: metrics of the current frame, the stability checks on them, then the hook
  auto sample = [&](long long step) {
    backend->frame(frame);
    Sample s;
    s.t = frame.t;
    s.metrics = measure(frame, weave, scene, metric_options);
    s.step_wall_ms = interval_steps ? 1e3 * interval_wall / interval_steps : 0.0;
    interval_wall = 0.0, interval_steps = 0;
    const Metrics& m = s.metrics;
    double growth = 0.0;
    if (m.non_finite == 0) {
      const double potential = potential_energy(frame, scene, masses);
      if (step == 0) {
        potential_start = potential, kinetic_start = m.kinetic_energy;
        energy_start = potential + m.kinetic_energy;
      }
      growth = potential + m.kinetic_energy - energy_start;
      run.peak_stretch = std::max(run.peak_stretch, m.max_stretch);
    }
    if (const std::string verdict = verdict_of(m, scene, growth, scale); !verdict.empty())
      run.stable = false, run.verdict = verdict;
    if (hook) hook(frame, s);
    run.last = s;
    ++run.samples;
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

    // a signal or the watchdog end the run here, with a last sample of where it got to
    const bool watchdog =
        options.max_wall_seconds > 0.0 && seconds_since(started) > options.max_wall_seconds;
    if (keep_going && step < total_steps && (interrupted() || watchdog)) {
      if (step % steps_per_sample != 0) sample(step);  // where it got to, unless just sampled
      run.stable = false;
      run.verdict = interrupted() ? "interrupted" : "watchdog";
      break;
    }
    progress.update(step * run.dt, run.ms_per_step());
  }
  progress.finish(run.steps * run.dt, run.ms_per_step(), run.verdict);

  backend->frame(run.final_frame);
  run.hash = frame_hash(run.final_frame);
  run.stages = backend->profile().stages();
  if (weave.type != WeaveType::grid && run.samples > 0)
    run.overstretched = run.peak_stretch > 1.0 + kOverstretchTolerance;
  if (run.stable && run.final_metrics().non_finite == 0) {
    // settled: little kinetic energy left of what gravity and the initial velocity gave the run
    const double given = std::max(
        potential_start - potential_energy(run.final_frame, scene, masses) + kinetic_start, 0.0);
    run.settled =
        run.final_metrics().kinetic_energy <= kSettledEnergyFraction * given + 1e-12 * scale;
  }
  return run;
}

std::string scene_content_hash(const Scene& scene, const std::string& backend) {
  nlohmann::json key = scene.resolved;
  key.erase("output");
  key.erase("camera");
  key.erase("description");
  key.erase("reference_dt");
  key.erase("reference");
  const BackendInfo* info = find_backend(backend);
  nlohmann::json knobs = nlohmann::json::object();
  if (info) {
    for (const auto& [k, v] : resolve_knobs(scene, *info)) knobs[k] = v;
  }
  key["backends"] = {{backend, knobs}};
  // the build too: a changed backend is never measured against its old self
  key["build"] = chainmail_version() + " " + chainmail_commit();
  const std::string text = key.dump();
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char ch : text) h = (h ^ ch) * 0x100000001b3ull;
  return hex(h);
}

std::string reference_backend(const Scene& scene, const RunOptions& options) {
  const std::string name = options.reference.empty() ? scene.reference : options.reference;
  return name == "none" ? "" : name;
}

Scene reference_scene(const Scene& scene, const std::string& reference) {
  if (scene.reference_dt <= 0.0) return scene;
  nlohmann::json doc = scene.resolved;
  doc["backends"][reference]["dt"] = scene.reference_dt;
  return scene_from_json(doc, scene.file);
}

std::string reference_cache_path(const Scene& scene, const std::string& reference,
                                 const std::string& cache_dir) {
  if (cache_dir.empty()) return "";
  return cache_dir + "/" + scene.name + "-" + reference + "-" +
         scene_content_hash(reference_scene(scene, reference), reference) + ".frames";
}

namespace {

// warn once per process that the cache cannot be used; runs go on without it
void cache_warning(const std::string& what) {
  static bool warned = false;
  if (warned) return;
  warned = true;
  std::fprintf(stderr, "chainmail: warning: reference cache: %s (going on without it)\n",
               what.c_str());
}

// a cache folder that can be written ("" when it cannot: warned)
bool usable_cache_dir(const std::string& dir) {
  if (dir.empty()) return false;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir) || ::access(dir.c_str(), W_OK) != 0) {
    cache_warning("cannot write " + dir + (ec ? ": " + ec.message() : ""));
    return false;
  }
  return true;
}

void store_in_cache(const std::string& stream, const std::string& path) {
  if (path.empty() || !usable_cache_dir(fs::path(path).parent_path().string())) return;
  if (!copy_stream(stream, path)) cache_warning("cannot write " + path);
}

// where the reference run's frames come from while the other runs are measured
struct ReferenceSource {
  std::string backend;                // "" = no reference (drape_rms absent)
  bool from_selected = false;         // one of the selected runs is the reference
  std::optional<FrameReader> reader;  // open once the reference frames exist
  std::string note;
  RingFrame frame;  // the reference frame last read
  std::size_t index = static_cast<std::size_t>(-1);

  // drape_rms of a frame against the reference frame nearest in time (nullopt without one)
  std::optional<double> drape(const RingFrame& f) {
    if (!reader || reader->count() == 0) return std::nullopt;
    const std::size_t k = reader->nearest(f.t);
    if (k != index && !reader->read(k, frame)) return std::nullopt;
    index = k;
    return drape_rms(f, frame);
  }
};

// streams one backend's samples into the run folder: its metric rows, its frames when kept, the
// frame CSVs when asked; a frame that is not finite is never written
class SampleWriter {
 public:
  SampleWriter(const RunOptions& options, const std::string& name, const Weave& weave,
               const std::string& stream_path)
      : options_(options), name_(name), weave_(weave) {
    if (!options.folder.empty()) {
      fs::create_directories(options.folder + "/.streams");
      rows_.open(options.folder + "/.streams/" + name + ".csv");
      if (options.frame_csv) fs::create_directories(options.folder + "/frames/" + name);
    }
    if (!stream_path.empty()) frames_ = std::make_unique<FrameWriter>(stream_path, weave.size());
  }
  void write(const RingFrame& frame, const Sample& sample) {
    if (rows_.is_open()) rows_ << metrics_row(name_, sample);
    if (sample.metrics.non_finite > 0) return;
    if (frames_) frames_->append(frame);
    if (options_.frame_csv && !options_.folder.empty()) {
      char file[32];
      std::snprintf(file, sizeof file, "/%05lld.csv", frame_index_);
      write_file_atomic(options_.folder + "/frames/" + name_ + file, frame_csv(frame, weave_));
    }
    ++frame_index_;
  }
  bool finish() {
    if (rows_.is_open()) {
      rows_.close();
      if (rows_.fail()) throw std::runtime_error("cannot write the metric rows of " + name_);
    }
    return !frames_ || frames_->close();
  }

 private:
  const RunOptions& options_;
  std::string name_;
  const Weave& weave_;
  std::ofstream rows_;
  std::unique_ptr<FrameWriter> frames_;
  long long frame_index_ = 0;
};

// a temporary file for a reference stream when the run writes no folder
std::string temporary_stream_path() {
  static int counter = 0;
  return (fs::temp_directory_path() / ("chainmail-reference-" + std::to_string(::getpid()) + "-" +
                                       std::to_string(counter++) + ".frames"))
      .string();
}

// one backend with its samples streamed; `is_reference`: its frames are the reference
BackendRun run_streamed(const Scene& scene, const Weave& weave, const std::string& name,
                        const RunOptions& options, ReferenceSource& reference, bool is_reference) {
  std::string stream;
  if (is_reference || options.keep_stream) {
    stream = options.folder.empty() ? temporary_stream_path()
                                    : options.folder + "/.streams/" + name + ".frames";
  }
  SampleWriter writer(options, name, weave, stream);
  BackendRun run = run_backend(scene, weave, name, options, [&](const RingFrame& f, Sample& s) {
    if (s.metrics.non_finite == 0)
      s.metrics.drape_rms = is_reference ? std::optional<double>(0.0) : reference.drape(f);
    writer.write(f, s);
  });
  if (!writer.finish() && !stream.empty()) {
    std::fprintf(stderr, "chainmail: warning: cannot write the frames of %s\n", name.c_str());
    stream.clear();
  }
  run.stream = stream;
  return run;
}

}  // namespace

bool ensure_reference_cached(const Scene& scene, const std::string& reference,
                             const RunOptions& options) {
  const std::string path = reference_cache_path(scene, reference, options.cache_dir);
  if (path.empty()) return false;
  const Weave weave = make_weave(scene.weave, scene.ring);
  if (FrameReader::open(path, weave.size())) return true;
  if (!usable_cache_dir(options.cache_dir)) return false;
  RunOptions quiet = options;
  quiet.folder.clear();
  quiet.other_pair_metrics = false;
  ReferenceSource none;
  const BackendRun run =
      run_streamed(reference_scene(scene, reference), weave, reference, quiet, none, true);
  if (run.stable && !run.stream.empty()) store_in_cache(run.stream, path);
  std::error_code ignored;
  fs::remove(run.stream, ignored);
  return run.stable && FrameReader::open(path, weave.size()).has_value();
}

SceneRun run_scene(const Scene& scene, const RunOptions& options) {
  SceneRun result;
  result.scene = scene;
  result.weave = make_weave(scene.weave, scene.ring);
  validate_backend_knobs(scene);
  const std::vector<std::string> names = select_backends(scene, options.backends);

  // the reference: from the cache, from a selected run at the reference dt (run first), or a run
  // of its own before the others
  ReferenceSource reference;
  reference.backend = reference_backend(scene, options);
  std::string cache_path, temporary;
  std::vector<std::string> order = names;
  if (!reference.backend.empty()) {
    const Scene ref_scene = reference_scene(scene, reference.backend);
    const double ref_dt = resolve_knobs(ref_scene, *find_backend(reference.backend)).at("dt");
    cache_path = reference_cache_path(scene, reference.backend, options.cache_dir);
    if (!cache_path.empty()) reference.reader = FrameReader::open(cache_path, result.weave.size());
    const auto selected = std::find(order.begin(), order.end(), reference.backend);
    if (!reference.reader && selected != order.end() &&
        resolve_knobs(scene, *find_backend(reference.backend)).at("dt") == ref_dt) {
      reference.from_selected = true;
      std::rotate(order.begin(), selected, selected + 1);
    } else if (!reference.reader) {
      if (options.progress) {
        std::fprintf(stderr,
                     "%s: reference run: %s at dt %g s for drape_rms, about %s "
                     "(--reference none skips it)\n",
                     scene.name.c_str(), reference.backend.c_str(), ref_dt,
                     human_duration(estimate_seconds(ref_scene, reference.backend)).c_str());
      }
      RunOptions quiet = options;
      quiet.other_pair_metrics = false;
      quiet.keep_stream = false;
      quiet.frame_csv = false;
      quiet.folder.clear();
      ReferenceSource none;
      const BackendRun run =
          run_streamed(ref_scene, result.weave, reference.backend, quiet, none, true);
      temporary = run.stream;
      if (run.stable && !run.stream.empty()) {
        reference.reader = FrameReader::open(run.stream, result.weave.size());
        store_in_cache(run.stream, cache_path);
      }
    }
  }

  // every backend in turn, each one's samples on disk as they are taken
  std::vector<BackendRun> done;
  for (const auto& name : order) {
    if (interrupted()) break;
    if (options.progress) std::fprintf(stderr, "%s: %s\n", scene.name.c_str(), name.c_str());
    const bool is_reference = reference.from_selected && name == reference.backend;
    done.push_back(run_streamed(scene, result.weave, name, options, reference, is_reference));
    BackendRun& run = done.back();
    if (run.stable) run.catenary_error = catenary_error(scene, result.weave, run.final_frame);
    if (is_reference && run.stable && !run.stream.empty()) {
      reference.reader = FrameReader::open(run.stream, result.weave.size());
      store_in_cache(run.stream, cache_path);
    }
    // only the reference needed it
    if (is_reference && !options.keep_stream) {
      if (options.folder.empty()) temporary = run.stream;
      run.stream.clear();
    }
  }
  if (!temporary.empty()) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
  }
  result.interrupted = interrupted();

  // the results in the order asked for; what a signal stopped before it started is "interrupted"
  for (const auto& name : names) {
    auto it = std::find_if(done.begin(), done.end(), [&](const auto& r) { return r.name == name; });
    if (it != done.end()) {
      result.runs.push_back(std::move(*it));
      continue;
    }
    BackendRun skipped;
    skipped.name = name;
    skipped.knobs = resolve_knobs(scene, *find_backend(name));
    skipped.dt = skipped.knobs.at("dt");
    skipped.stable = false;
    skipped.verdict = "interrupted";
    result.runs.push_back(skipped);
  }
  if (reference.backend.empty())
    result.reference_note = "no reference run (--reference none): drape_rms absent";
  else if (!reference.reader)
    result.reference_note = "no stable reference run (" + reference.backend + "): drape_rms absent";
  else
    result.reference_note = "drape_rms against " + reference.backend;
  return result;
}

}  // namespace chainmail

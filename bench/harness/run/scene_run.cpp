// One scene through the selected backends: which backends, their samples streamed to disk, and
// drape_rms against the reference as the samples come.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>

#include "backends/backend.hpp"
#include "bench/harness/common/interrupt.hpp"
#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/output/frame_stream.hpp"
#include "bench/harness/output/output.hpp"
#include "bench/harness/output/output_error.hpp"
#include "bench/harness/reference/reference.hpp"
#include "bench/harness/run/run.hpp"
#include "core/metrics.hpp"

namespace chainmail {
namespace fs = std::filesystem;

namespace {

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
      if (rows_.fail()) throw_write_error("the metric rows of " + name_, errno);
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

// the backends the scene configures (all when it names none) that are built into this binary, in
// the registry's order; the others are skipped with one note
std::vector<std::string> scene_backends(const Scene& scene) {
  std::vector<std::string> names, skipped;
  for (const auto& name : known_backend_names()) {
    if (!scene.backends.empty() && !scene.backends.contains(name)) continue;
    if (backend_built(name))
      names.push_back(name);
    else if (!scene.backends.empty())
      skipped.push_back(name);
  }
  if (names.empty()) {
    throw UsageError(scene.file + ": none of the scene's backends (" + join_names(skipped) +
                     ") is built into this binary (built: " + join_names(built_backend_names()) +
                     ")");
  }
  if (!skipped.empty()) {
    std::fprintf(stderr, "%s: %s not built into this binary: skipped, knobs not checked\n",
                 scene.name.c_str(), join_names(skipped).c_str());
  }
  return names;
}

// an explicit --backends list, each name once; a name that is empty, unknown or not built into
// this binary is a usage error
std::vector<std::string> listed_backends(const std::vector<std::string>& requested) {
  const std::string known = join_names(built_backend_names());
  std::vector<std::string> names;
  for (const auto& name : requested) {
    if (name.empty())
      throw UsageError("--backends: an empty name in the list (known: " + known + ", all)");
    if (backend_known_unbuilt(name)) {
      throw UsageError("--backends: " + name + " is not built into this binary (built: " + known +
                       ")");
    }
    if (!find_backend(name))
      throw UsageError("--backends: unknown backend '" + name + "' (known: " + known + ", all)");
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  return names;
}

// every backend in turn, each one's samples on disk as they are taken; stops at a signal
std::vector<BackendRun> run_each(const Scene& scene, const Weave& weave,
                                 const std::vector<std::string>& order, const RunOptions& options,
                                 ReferenceSource& reference) {
  std::vector<BackendRun> done;
  for (const auto& name : order) {
    if (interrupted()) break;
    if (options.progress) std::fprintf(stderr, "%s: %s\n", scene.name.c_str(), name.c_str());
    const bool is_reference = reference.from_selected && name == reference.backend;
    BackendRun run = run_streamed(scene, weave, name, options, reference, is_reference);
    if (run.stable) run.catenary_error = catenary_error(scene, weave, run.final_frame);
    if (is_reference) reference.adopt(run, options, weave.size());
    done.push_back(std::move(run));
  }
  return done;
}

// a backend a signal kept from starting: verdict interrupted, no samples
BackendRun not_started(const Scene& scene, const std::string& name) {
  BackendRun run;
  run.name = name;
  run.knobs = resolve_knobs(scene, *find_backend(name));
  run.dt = run.knobs.at("dt");
  run.stable = false;
  run.verdict = Verdict::interrupted;
  return run;
}

// the runs in the order asked for, the ones that did not start included
std::vector<BackendRun> in_order_asked(const Scene& scene, const std::vector<std::string>& names,
                                       std::vector<BackendRun> done) {
  std::vector<BackendRun> runs;
  for (const auto& name : names) {
    auto it = std::find_if(done.begin(), done.end(), [&](const auto& r) { return r.name == name; });
    runs.push_back(it != done.end() ? std::move(*it) : not_started(scene, name));
  }
  return runs;
}

}  // namespace

std::vector<std::string> select_backends(const Scene& scene,
                                         const std::vector<std::string>& requested) {
  if (requested.empty()) return scene_backends(scene);
  if (requested.size() == 1 && requested[0] == kAllBackends) return built_backend_names();
  return listed_backends(requested);
}

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
    // frames in the output folder are part of the output; a temporary stream only feeds exports
    if (!options.folder.empty()) throw_write_error(stream, errno);
    std::fprintf(stderr, "chainmail: warning: cannot write the frames of %s\n", name.c_str());
    stream.clear();
  }
  run.stream = stream;
  return run;
}

SceneRun run_scene(const Scene& scene, const RunOptions& options) {
  SceneRun result;
  result.scene = scene;
  result.weave = make_weave(scene.weave, scene.ring);
  result.threads = options.threads;
  validate_backend_knobs(scene);
  const std::vector<std::string> names = select_backends(scene, options.backends);
  // the reference first: from the cache, a selected run moved to the front, or a run of its own
  std::vector<std::string> order = names;
  ReferenceSource reference = prepare_reference(scene, result.weave, options, order);
  std::vector<BackendRun> done = run_each(scene, result.weave, order, options, reference);
  reference.remove_temporary();
  result.interrupted = interrupted();
  result.runs = in_order_asked(scene, names, std::move(done));
  result.reference_note = reference.note();
  return result;
}

}  // namespace chainmail

// The reference run and its cache: a reference run is kept by the content hash of what determines
// its result, so that every later run of the same scene and build reads it instead of running it.
#include "bench/harness/reference/reference.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "bench/harness/common/version.hpp"
#include "bench/harness/run/budget.hpp"
#include "core/metrics.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace fs = std::filesystem;

namespace {

std::string hex(std::uint64_t value) {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(value));
  return buffer;
}

// the reference the scene or --reference names, built or not ("" for none)
std::string named_reference(const Scene& scene, const RunOptions& options) {
  const std::string name = options.reference.empty() ? scene.reference : options.reference;
  return name == kNoReference ? "" : name;
}

// warn once per process that the cache cannot be used; runs go on without it
void cache_warning(const std::string& what) {
  static bool warned = false;
  if (warned) return;
  warned = true;
  std::fprintf(stderr, "chainmail: warning: reference cache: %s (going on without it)\n",
               what.c_str());
}

// a cache folder that can be written (false when it cannot: warned)
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

// the reference backend on its own, nothing written but its frame stream
BackendRun run_reference_alone(const Scene& ref_scene, const Weave& weave,
                               const std::string& backend, const RunOptions& options) {
  RunOptions quiet = options;
  quiet.other_pair_metrics = false;
  quiet.keep_stream = false;
  quiet.frame_csv = false;
  quiet.folder.clear();
  ReferenceSource none;
  return run_streamed(ref_scene, weave, backend, quiet, none, true);
}

// a run of its own before the others, announced with its estimated time
void run_reference_first(const Scene& scene, const Weave& weave, const RunOptions& options,
                         ReferenceSource& reference) {
  const Scene ref_scene = reference_scene(scene, reference.backend);
  if (options.progress) {
    const double dt = resolve_knobs(ref_scene, *find_backend(reference.backend)).at("dt");
    std::fprintf(stderr,
                 "%s: reference run: %s at dt %g s for drape_rms, about %s "
                 "(--reference none skips it)\n",
                 scene.name.c_str(), reference.backend.c_str(), dt,
                 human_duration(estimate_seconds(ref_scene, reference.backend)).c_str());
  }
  const BackendRun run = run_reference_alone(ref_scene, weave, reference.backend, options);
  reference.temporary = run.stream;
  if (run.stable && !run.stream.empty()) {
    reference.reader = FrameReader::open(run.stream, weave.size());
    store_in_cache(run.stream, reference.cache_path);
  }
}

}  // namespace

std::string scene_content_hash(const Scene& scene, const std::string& backend) {
  nlohmann::json key = scene_to_json(scene);
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
  const std::string name = named_reference(scene, options);
  return find_backend(name) ? name : "";
}

Scene reference_scene(const Scene& scene, const std::string& reference) {
  if (scene.reference_dt <= 0.0) return scene;
  Scene out = scene;
  out.backends[reference]["dt"] = KnobValue{KnobValue::Kind::number, scene.reference_dt, {}};
  return out;
}

std::string reference_cache_path(const Scene& scene, const std::string& reference,
                                 const std::string& cache_dir) {
  if (cache_dir.empty()) return "";
  return cache_dir + "/" + scene.name + "-" + reference + "-" +
         scene_content_hash(reference_scene(scene, reference), reference) + ".frames";
}

std::optional<double> ReferenceSource::drape(const RingFrame& f) {
  if (!reader || reader->count() == 0) return std::nullopt;
  const std::size_t k = reader->nearest(f.t);
  if (k != index && !reader->read(k, frame)) return std::nullopt;
  index = k;
  return drape_rms(f, frame);
}

void ReferenceSource::adopt(BackendRun& run, const RunOptions& options, int rings) {
  if (run.stable && !run.stream.empty()) {
    reader = FrameReader::open(run.stream, rings);
    store_in_cache(run.stream, cache_path);
  }
  // only the reference needed its stream: a folder's goes with the folder's working files
  if (!options.keep_stream) {
    if (options.folder.empty()) temporary = run.stream;
    run.stream.clear();
  }
}

std::string ReferenceSource::note() const {
  if (!unbuilt.empty())
    return "no reference run (" + unbuilt + " is not built into this binary): drape_rms absent";
  if (backend.empty()) return "no reference run (--reference none): drape_rms absent";
  if (!reader) return "no stable reference run (" + backend + "): drape_rms absent";
  return "drape_rms against " + backend;
}

void ReferenceSource::remove_temporary() const {
  if (temporary.empty()) return;
  std::error_code ignored;
  fs::remove(temporary, ignored);
}

ReferenceSource prepare_reference(const Scene& scene, const Weave& weave, const RunOptions& options,
                                  std::vector<std::string>& order) {
  ReferenceSource reference;
  reference.backend = reference_backend(scene, options);
  if (const std::string named = named_reference(scene, options); named != reference.backend) {
    reference.unbuilt = named;
    std::fprintf(stderr, "%s: reference %s is not built into this binary: no drape_rms\n",
                 scene.name.c_str(), named.c_str());
  }
  if (reference.backend.empty()) return reference;

  // from the cache
  reference.cache_path = reference_cache_path(scene, reference.backend, options.cache_dir);
  if (!reference.cache_path.empty())
    reference.reader = FrameReader::open(reference.cache_path, weave.size());
  if (reference.reader) return reference;

  // from a selected run at the reference dt, run first
  const BackendInfo& info = *find_backend(reference.backend);
  const double ref_dt = resolve_knobs(reference_scene(scene, reference.backend), info).at("dt");
  const auto selected = std::find(order.begin(), order.end(), reference.backend);
  if (selected != order.end() && resolve_knobs(scene, info).at("dt") == ref_dt) {
    reference.from_selected = true;
    std::rotate(order.begin(), selected, selected + 1);
    return reference;
  }

  // a run of its own before the others
  run_reference_first(scene, weave, options, reference);
  return reference;
}

bool ensure_reference_cached(const Scene& scene, const std::string& reference,
                             const RunOptions& options) {
  const std::string path = reference_cache_path(scene, reference, options.cache_dir);
  if (path.empty() || !find_backend(reference)) return false;
  const Weave weave = make_weave(scene.weave, scene.ring);
  if (FrameReader::open(path, weave.size())) return true;
  if (!usable_cache_dir(options.cache_dir)) return false;
  const BackendRun run =
      run_reference_alone(reference_scene(scene, reference), weave, reference, options);
  if (run.stable && !run.stream.empty()) store_in_cache(run.stream, path);
  std::error_code ignored;
  fs::remove(run.stream, ignored);
  return run.stable && FrameReader::open(path, weave.size()).has_value();
}

}  // namespace chainmail

#include "bench/harness/commands/commands.hpp"

#include <cstdio>
#include <cstdlib>

#include "backends/backend.hpp"
#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/output/output.hpp"
#include "bench/harness/output/output_folder.hpp"
#include "bench/harness/output/render_output.hpp"
#include "bench/harness/report/report.hpp"
#include "bench/harness/run/run.hpp"
#include "core/parallel.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {

std::string default_cache_dir() {
  if (const char* dir = std::getenv("CHAINMAIL_CACHE_DIR"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::string(xdg) + "/chainmail";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::string(home) + "/.cache/chainmail";
  return "";
}

std::string resolve_cache_dir(const std::string& flag) {
  if (flag == kNoCache) return "";
  return flag.empty() ? default_cache_dir() : flag;
}

namespace {

// --reference: "" (the scene's), none, or a backend built into this binary
void check_reference_flag(const std::string& reference) {
  if (reference.empty() || reference == kNoReference || find_backend(reference)) return;
  if (backend_known_unbuilt(reference)) {
    throw UsageError("--reference: " + reference + " is not built into this binary (built: " +
                     join_names(built_backend_names()) + ")");
  }
  throw UsageError("--reference: unknown backend '" + reference + "' (or none)");
}

// the run's options from the command line and the scene (the folder is set once it is claimed)
RunOptions run_options(const RunCommand& command, const Scene& scene) {
  RunOptions options;
  options.backends = select_backends(scene, command.backends);
  options.progress = command.progress;
  options.cache_dir = resolve_cache_dir(command.cache_dir);
  check_reference_flag(command.reference);
  options.reference = command.reference;
  options.frame_csv = command.frames || scene.write_frames;
  options.keep_stream = command.render || !command.exports.empty();
  options.threads = command.threads > 0 ? command.threads : hardware_threads();
  return options;
}

// refuse a run estimated to need more memory, time or frame output than the budget allows
void check_run_budget(const Scene& scene, const RunOptions& options, const Budget& budget) {
  std::vector<std::string> estimated = options.backends;
  if (const std::string ref = reference_backend(scene, options); !ref.empty())
    estimated.push_back(ref);  // at worst it runs once more, uncached
  const double bytes_per_ring_sample =
      (options.frame_csv ? 90.0 : 0.0) + (options.keep_stream ? 56.0 : 0.0);
  check_budget(scene, estimate_run(scene, estimated, bytes_per_ring_sample), budget);
}

// refuse an export larger than its format can hold, before anything runs
void check_export_size(const Scene& scene) {
  const auto samples = static_cast<long long>(scene.duration / scene.sample_interval) + 2;
  if (const std::string why = export_size_refusal(make_weave(scene.weave, scene.ring), samples);
      !why.empty())
    throw UsageError(scene.file + ": key 'sample_interval': --export: " + why);
}

// one line per backend, then where the results are
void print_run_lines(const SceneRun& run, const std::string& path) {
  for (const auto& b : run.runs) {
    std::fprintf(stderr, "%-10s %8.3f ms/step  x%-8.2f real time  %s  hash %016llx\n",
                 b.name.c_str(), b.ms_per_step(), b.realtime_factor(), to_string(b.verdict),
                 static_cast<unsigned long long>(b.hash));
  }
  std::fprintf(stderr, "wrote %s%s\n", path.c_str(),
               run.interrupted ? " (interrupted: what finished)" : "");
}

}  // namespace

int run_command(const RunCommand& command) {
  // everything that can be bad input is checked before anything runs or is written
  Scene scene = load_scene_file(command.scene_file, command.overrides);
  validate_backend_knobs(scene);
  RunOptions options = run_options(command, scene);
  check_run_budget(scene, options, command.budget);
  OutputOptions output;
  output.exports = parse_export_formats(command.exports);
  if (!output.exports.empty()) check_export_size(scene);
  if (command.render)
    output.render =
        make_render_writer(command.shader, command.material);  // checks GL + shaders first

  const std::string path =
      command.out_dir.empty() ? "results/" + scene.name + "/run" : command.out_dir;
  OutputFolder folder = OutputFolder::claim(path, "run", command.force);
  options.folder = folder.staging();
  const SceneRun run = run_scene(scene, options);
  write_run_folder(run, folder.staging(), output);
  if (command.report) write_report_beside(folder.staging(), "run");
  folder.commit();

  print_run_lines(run, path);
  if (run.interrupted) return kExitInterrupted;
  return run.all_stable() ? kExitOk : kExitUnstable;
}

}  // namespace chainmail

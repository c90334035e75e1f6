#include "bench/harness/commands.hpp"

#include <cstdio>
#include <cstdlib>

#include "bench/harness/output.hpp"
#include "bench/harness/output_folder.hpp"
#include "bench/harness/render_output.hpp"
#include "bench/harness/run.hpp"

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
  if (flag == "none") return "";
  return flag.empty() ? default_cache_dir() : flag;
}

int run_command(const RunCommand& command) {
  // everything that can be bad input is checked before anything runs or is written
  Scene scene = load_scene_file(command.scene_file, command.overrides);
  validate_backend_knobs(scene);
  RunOptions options;
  options.backends = select_backends(scene, command.backends);
  options.progress = command.progress;
  options.cache_dir = resolve_cache_dir(command.cache_dir);
  options.reference = command.reference;
  if (!options.reference.empty() && options.reference != "none" &&
      !find_backend(options.reference)) {
    throw SceneError("--reference: unknown backend '" + options.reference + "' (or none)");
  }
  options.frame_csv = command.frames || scene.write_frames;
  options.keep_stream = command.render;
  std::vector<std::string> estimated = options.backends;
  if (const std::string ref = reference_backend(scene, options); !ref.empty())
    estimated.push_back(ref);  // at worst it runs once more, uncached
  const double bytes_per_ring_sample =
      (options.frame_csv ? 90.0 : 0.0) + (options.keep_stream ? 56.0 : 0.0);
  check_budget(scene, estimate_run(scene, estimated, bytes_per_ring_sample), command.budget);
  OutputOptions output;
  if (command.render)
    output.render =
        make_render_writer(command.shader, command.material);  // checks GL + shaders first

  const std::string path =
      command.out_dir.empty() ? "results/" + scene.name + "/run" : command.out_dir;
  OutputFolder folder = OutputFolder::claim(path, "run", command.force);
  options.folder = folder.staging();
  const SceneRun run = run_scene(scene, options);
  write_run_folder(run, folder.staging(), output);
  folder.commit();

  for (const auto& b : run.runs) {
    std::fprintf(stderr, "%-10s %8.3f ms/step  x%-8.2f real time  %s  hash %016llx\n",
                 b.name.c_str(), b.ms_per_step(), b.realtime_factor(), b.verdict.c_str(),
                 static_cast<unsigned long long>(b.hash));
  }
  std::fprintf(stderr, "wrote %s%s\n", path.c_str(),
               run.interrupted ? " (interrupted: what finished)" : "");
  if (run.interrupted) return kExitInterrupted;
  return run.all_stable() ? kExitOk : kExitUnstable;
}

}  // namespace chainmail

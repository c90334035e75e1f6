#include "bench/harness/commands.hpp"

#include <cstdio>

#include "bench/harness/output.hpp"
#include "bench/harness/render_output.hpp"
#include "bench/harness/run.hpp"

namespace chainmail {

int run_command(const RunCommand& command) {
  Scene scene = load_scene_file(command.scene_file, command.overrides);
  validate_backend_knobs(scene);
  RunOptions options;
  options.backends = command.backends;
  options.progress = command.progress;
  options.cache_dir = command.cache_dir;
  select_backends(scene, options.backends);  // refuse unknown names before any work
  OutputOptions output;
  output.frames = command.frames || scene.write_frames;
  if (command.render)
    output.render =
        make_render_writer(command.shader, command.material);  // checks GL + shaders first

  const SceneRun run = run_scene(scene, options);
  const std::string folder = command.out_dir.empty() ? "results/" + scene.name : command.out_dir;
  write_run_folder(run, folder, output);

  for (const auto& b : run.runs) {
    std::fprintf(stderr, "%-10s %8.3f ms/step  x%-8.2f real time  %s  hash %016llx\n",
                 b.name.c_str(), b.ms_per_step(), b.realtime_factor(), b.verdict.c_str(),
                 static_cast<unsigned long long>(b.hash));
  }
  std::fprintf(stderr, "wrote %s\n", folder.c_str());
  return run.all_stable() ? kExitOk : kExitUnstable;
}

}  // namespace chainmail

// chainmail: run scenes through every model, measure, compare, render.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "bench/harness/commands.hpp"
#include "core/scene.hpp"

int main(int argc, char** argv) {
  using namespace chainmail;
  CLI::App app{"chainmail: a physics comparison harness for interlocking-ring fabric"};
  app.require_subcommand(1);

  RunCommand run;
  CLI::App* run_app = app.add_subcommand("run", "run one scene through one or more backends");
  run_app->add_option("scene", run.scene_file, "scene file (JSON)")->required();
  run_app->add_option("--backends", run.backends, "backends to run: a list, or all")->delimiter(',');
  run_app->add_option("--out", run.out_dir, "output folder (default results/<scene name>)");
  run_app->add_flag("--frames", run.frames, "write frames/<backend>/<NNNNN>.csv");
  run_app->add_flag("--render", run.render, "render side-by-side PNG frames into images/");
  run_app->add_option("--shader", run.shader, "cloth shader for --render");
  run_app->add_option("--set", run.overrides, "override a scene key: dotted.key=value");
  run_app->add_option("--cache", run.cache_dir, "reference-run cache folder");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "chainmail: %s\n", e.what());
    return kExitBadInput;
  }

  try {
    if (*run_app) return run_command(run);
  } catch (const SceneError& e) {
    std::fprintf(stderr, "chainmail: %s\n", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainmail: internal error: %s\n", e.what());
    return kExitInternal;
  }
  return kExitOk;
}

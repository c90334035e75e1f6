// chainmail: run scenes through every model, measure, compare, render.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "bench/harness/commands.hpp"
#include "bench/harness/suites.hpp"
#include "core/scene.hpp"

#include <filesystem>

namespace {
// this binary, so sweep points run the very same build
std::string self_path(const char* argv0) {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(argv0) : exe.string();
}
}  // namespace

int main(int argc, char** argv) {
  using namespace chainmail;
  CLI::App app{"chainmail: a physics comparison harness for interlocking-ring fabric"};
  app.require_subcommand(1);

  RunCommand run;
  CLI::App* run_app = app.add_subcommand("run", "run one scene through one or more backends");
  run_app->add_option("scene", run.scene_file, "scene file (JSON)")->required();
  run_app->add_option("--backends", run.backends, "backends to run: a list, or all")
      ->delimiter(',');
  run_app->add_option("--out", run.out_dir, "output folder (default results/<scene name>)");
  run_app->add_flag("--frames", run.frames, "write frames/<backend>/<NNNNN>.csv");
  run_app->add_flag("--render", run.render, "render side-by-side PNG frames into images/");
  run_app->add_option(
      "--shader", run.shader,
      "cloth shader for --render: blinn_phong, texture, bump, displacement, mirror");
  run_app->add_option("--material", run.material,
                      "ring material for --render: steel, silver, gold, copper, brass, bronze, "
                      "titanium");
  run_app->add_option("--set", run.overrides, "override a scene key: dotted.key=value");
  run_app->add_option("--cache", run.cache_dir, "reference-run cache folder");
  bool run_quiet = false;
  run_app->add_flag("--quiet", run_quiet, "no progress lines");

  SweepCommand sweep;
  CLI::App* sweep_app =
      app.add_subcommand("sweep", "error against run time over a grid of knob values");
  sweep_app->add_option("scene", sweep.scene_file, "scene file (JSON)")->required();
  sweep_app->add_option("--vary", sweep.vary, "KEY=v1,v2,... ({backend} in KEY: each backend)")
      ->required();
  sweep_app->add_option("--backends", sweep.backends, "backends: a list, or all")->delimiter(',');
  sweep_app->add_option("--set", sweep.overrides, "override a scene key for every point");
  sweep_app->add_option("--out", sweep.out_dir, "output folder (default results/<scene>/sweep)");
  sweep_app->add_option("--jobs", sweep.jobs, "points run in parallel")->check(CLI::Range(1, 256));
  sweep_app->add_flag("--print-jobs", sweep.print_jobs, "print each point's command line and stop");
  sweep_app->add_option("--cache", sweep.cache_dir, "reference-run cache folder");

  StabilityCommand stability;
  CLI::App* stability_app =
      app.add_subcommand("stability", "stiff and extreme cases: verdicts and largest stable dt");
  stability_app->add_option("--backends", stability.backends, "backends: a list, or all")
      ->delimiter(',');
  stability_app->add_option("--out", stability.out_dir, "output folder");
  stability_app->add_flag("--quick", stability.quick, "tiny sizes (test mode)");
  stability_app->add_option("--max-wall", stability.max_wall_seconds, "watchdog per run, s")
      ->check(CLI::PositiveNumber);

  BenchCommand bench;
  CLI::App* bench_app =
      app.add_subcommand("bench", "the default scene set across all backends, writing results/");
  bench_app->add_option("--out", bench.out_dir, "output folder");
  bench_app->add_flag("--quick", bench.quick, "reduced sizes and durations (test mode)");
  bench_app->add_option("--backends", bench.backends, "backends: a list, or all")->delimiter(',');
  bench_app->add_option("--jobs", bench.jobs, "sweep points in parallel")
      ->check(CLI::Range(1, 256));
  bool no_render = false;
  bench_app->add_flag("--no-render", no_render, "skip the side-by-side frames");

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
    if (*run_app) {
      run.progress = !run_quiet;
      return run_command(run);
    }
    if (*sweep_app) {
      sweep.executable = self_path(argv[0]);
      return sweep_command(sweep);
    }
    if (*stability_app) return stability_command(stability);
    if (*bench_app) {
      bench.executable = self_path(argv[0]);
      bench.render = !no_render;
      return bench_command(bench);
    }
  } catch (const SceneError& e) {
    std::fprintf(stderr, "chainmail: %s\n", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainmail: internal error: %s\n", e.what());
    return kExitInternal;
  }
  return kExitOk;
}

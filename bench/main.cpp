// chainmail: run scenes through every model, measure, compare, render.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "bench/harness/commands.hpp"
#include "bench/harness/interrupt.hpp"
#include "bench/harness/suites.hpp"
#include "bench/harness/version.hpp"
#include "core/scene.hpp"

namespace {
// this binary, so sweep points run the very same build
std::string self_path(const char* argv0) {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(argv0) : exe.string();
}
// --backends a,b,c: every name non-empty ("all" alone means every backend)
std::vector<std::string> backend_list(const std::string& flag, const std::string& text) {
  std::vector<std::string> names;
  std::stringstream stream(text);
  for (std::string name; std::getline(stream, name, ',');) names.push_back(name);
  if (text.empty() || text.back() == ',') names.push_back("");
  for (const auto& name : names) {
    if (name.empty())
      throw chainmail::SceneError(flag + " '" + text + "': an empty name in the list");
  }
  return names;
}

// a flag's number must be finite and positive
void check_positive(const std::string& flag, double value) {
  if (!std::isfinite(value) || value <= 0.0) {
    std::ostringstream got;
    got << value;
    throw chainmail::SceneError(flag + ": must be a positive finite number, got " + got.str());
  }
}

// the budget flags of a command
void add_budget(CLI::App* app, chainmail::Budget& budget) {
  app->add_option("--max-memory", budget.max_memory_gb,
                  "refuse runs estimated to need more memory, GB (default 8)");
  app->add_option("--max-hours", budget.max_hours,
                  "refuse runs estimated to take longer, hours (default 2)");
  app->add_option("--max-output", budget.max_output_gb,
                  "refuse runs estimated to write more frame data, GB (default 20)");
}

void check_budget_flags(const chainmail::Budget& budget) {
  check_positive("--max-memory", budget.max_memory_gb);
  check_positive("--max-hours", budget.max_hours);
  check_positive("--max-output", budget.max_output_gb);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace chainmail;
  CLI::App app{"chainmail: a physics comparison harness for interlocking-ring fabric"};
  app.require_subcommand(1);
  app.set_version_flag("--version", chainmail_version() + " (" + chainmail_commit() + ", " +
                                        chainmail_build() + ")");

  RunCommand run;
  CLI::App* run_app = app.add_subcommand("run", "run one scene through one or more backends");
  run_app->add_option("scene", run.scene_file, "scene file (JSON)")->required();
  std::string run_backends, sweep_backends, stability_backends, bench_backends;
  run_app->add_option("--backends", run_backends, "backends to run: a list, or all");
  run_app->add_option("--out", run.out_dir,
                      "output folder (default results/<scene name>/run); only a folder chainmail "
                      "made is replaced");
  run_app->add_flag("--force", run.force, "replace an empty folder chainmail did not make");
  run_app->add_option("--reference", run.reference,
                      "backend drape_rms is measured against (default: the scene's), or none");
  add_budget(run_app, run.budget);
  run_app->add_flag("--frames", run.frames, "write frames/<backend>/<NNNNN>.csv");
  run_app->add_flag("--render", run.render, "render side-by-side PNG frames into images/");
  run_app->add_option(
      "--shader", run.shader,
      "cloth shader for --render: blinn_phong, texture, bump, displacement, mirror");
  run_app->add_option("--material", run.material,
                      "ring material for --render: steel, silver, gold, copper, brass, bronze, "
                      "titanium");
  run_app->add_option("--set", run.overrides, "override a scene key: dotted.key=value");
  run_app->add_option("--cache", run.cache_dir,
                      "reference-run cache folder, or none (default ~/.cache/chainmail)");
  bool run_quiet = false;
  run_app->add_flag("--quiet", run_quiet, "no progress lines");

  SweepCommand sweep;
  CLI::App* sweep_app =
      app.add_subcommand("sweep", "error against run time over a grid of knob values");
  sweep_app->add_option("scene", sweep.scene_file, "scene file (JSON)")->required();
  sweep_app->add_option("--vary", sweep.vary, "KEY=v1,v2,... ({backend} in KEY: each backend)")
      ->required();
  sweep_app->add_option("--backends", sweep_backends, "backends: a list, or all");
  sweep_app->add_option("--set", sweep.overrides, "override a scene key for every point");
  sweep_app->add_option("--out", sweep.out_dir, "output folder (default results/<scene>/sweep)");
  sweep_app->add_flag("--force", sweep.force, "replace an empty folder chainmail did not make");
  sweep_app->add_option("--jobs", sweep.jobs, "points run in parallel")->check(CLI::Range(1, 256));
  sweep_app->add_flag("--print-jobs", sweep.print_jobs, "print each point's command line and stop");
  sweep_app->add_option("--cache", sweep.cache_dir,
                        "reference-run cache folder, or none (default ~/.cache/chainmail)");

  StabilityCommand stability;
  CLI::App* stability_app =
      app.add_subcommand("stability", "stiff and extreme cases: verdicts and largest stable dt");
  stability_app->add_option("--backends", stability_backends, "backends: a list, or all");
  stability_app->add_option("--out", stability.out_dir,
                            "output folder (default results/stability)");
  stability_app->add_flag("--force", stability.force,
                          "replace an empty folder chainmail did not make");
  stability_app->add_flag("--quick", stability.quick, "tiny sizes (test mode)");
  stability_app->add_option("--max-wall", stability.max_wall_seconds,
                            "watchdog per run, s (default 30)");

  BenchCommand bench;
  CLI::App* bench_app = app.add_subcommand(
      "bench", "the default scene set across all backends, writing results/bench");
  bench_app->add_option("--out", bench.out_dir, "output folder (default results/bench)");
  bench_app->add_flag("--force", bench.force, "replace an empty folder chainmail did not make");
  bench_app->add_flag("--quick", bench.quick, "reduced sizes and durations (test mode)");
  bench_app->add_option("--backends", bench_backends, "backends: a list, or all");
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
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "chainmail: %s\n", e.what());
    return kExitBadInput;
  }

  install_interrupt_handlers();
  try {
    // an --out given empty is a mistake, not a request for the default folder
    for (CLI::App* sub : {run_app, sweep_app, stability_app, bench_app}) {
      if (*sub && sub->count("--out")) {
        const std::string out = sub->get_option("--out")->as<std::string>();
        if (out.find_first_not_of(" \t\r\n") == std::string::npos)
          throw SceneError("--out: an empty path");
      }
    }
    if (*run_app) {
      if (run_app->count("--backends")) run.backends = backend_list("--backends", run_backends);
      if (!run.render && (run_app->count("--shader") || run_app->count("--material")))
        throw SceneError(std::string(run_app->count("--shader") ? "--shader" : "--material") +
                         ": only with --render");
      check_budget_flags(run.budget);
      run.progress = !run_quiet;
      return run_command(run);
    }
    if (*sweep_app) {
      if (sweep_app->count("--backends"))
        sweep.backends = backend_list("--backends", sweep_backends);
      sweep.executable = self_path(argv[0]);
      return sweep_command(sweep);
    }
    if (*stability_app) {
      if (stability_app->count("--backends"))
        stability.backends = backend_list("--backends", stability_backends);
      check_positive("--max-wall", stability.max_wall_seconds);
      return stability_command(stability);
    }
    if (*bench_app) {
      if (bench_app->count("--backends"))
        bench.backends = backend_list("--backends", bench_backends);
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

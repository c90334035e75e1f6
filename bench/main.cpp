// chainmail: run scenes through every model, measure, compare, render.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>
#include <sstream>

#include "backends/backend.hpp"
#include "bench/harness/commands/commands.hpp"
#include "bench/harness/commands/info_commands.hpp"
#include "bench/harness/commands/render_command.hpp"
#include "bench/harness/common/data_dir.hpp"
#include "bench/harness/common/interrupt.hpp"
#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/common/version.hpp"
#include "bench/harness/output/output_error.hpp"
#include "bench/harness/report/report.hpp"
#include "bench/harness/suites/bench_suite.hpp"
#include "bench/harness/suites/stability.hpp"
#include "bench/harness/suites/sweep.hpp"
#include "core/scene.hpp"

namespace {

using chainmail::UsageError;

// each subcommand: what it runs, and the flags that are checked or converted before it runs
struct RunFlags {
  CLI::App* app = nullptr;
  chainmail::RunCommand command;
  std::string backends;
  bool quiet = false;
};
struct SweepFlags {
  CLI::App* app = nullptr;
  chainmail::SweepCommand command;
  std::string backends;
};
struct StabilityFlags {
  CLI::App* app = nullptr;
  chainmail::StabilityCommand command;
  std::string backends;
};
struct BenchFlags {
  CLI::App* app = nullptr;
  chainmail::BenchCommand command;
  std::string backends;
  bool no_render = false;
  bool no_scaling = false;
};
struct InfoFlags {
  CLI::App* backends = nullptr;
  bool json = false;
  CLI::App* check = nullptr;
  chainmail::CheckCommand check_command;
};

// the --backends help: every backend this binary knows, those it cannot run marked
std::string backends_help(const std::string& what) {
  std::string names;
  for (const std::string& name : chainmail::known_backend_names())
    names +=
        (names.empty() ? "" : ", ") + name + (chainmail::backend_built(name) ? "" : " (not built)");
  return what + ": a comma-separated list of " + names + "; or all";
}

// --threads N: threads each backend run steps on (the result does not depend on it)
void add_threads(CLI::App& sub, int& threads, const std::string& fallback) {
  sub.add_option("--threads", threads,
                 "threads each backend run steps on (default: " + fallback +
                     "); results are the same for any count")
      ->check(CLI::Range(1, 4096))
      ->default_str("");
}

struct RenderFlags {
  CLI::App* app = nullptr;
  chainmail::RenderCommand command;
  std::string backends;
  bool no_images = false;
};

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
    if (name.empty()) throw UsageError(flag + " '" + text + "': an empty name in the list");
  }
  return names;
}

// the --backends list of a subcommand, when given
void read_backends(CLI::App* app, const std::string& text, std::vector<std::string>& backends) {
  if (app->count("--backends")) backends = backend_list("--backends", text);
}

// a flag's number must be finite and positive
void check_positive(const std::string& flag, double value) {
  if (!std::isfinite(value) || value <= 0.0) {
    std::ostringstream got;
    got << value;
    throw UsageError(flag + ": must be a positive finite number, got " + got.str());
  }
}

// the budget flags of a command
void add_budget(CLI::App* app, chainmail::Budget& budget) {
  app->add_option("--max-memory", budget.max_memory_gb,
                  "refuse runs estimated to need more memory, GB");
  app->add_option("--max-hours", budget.max_hours, "refuse runs estimated to take longer, hours");
  app->add_option("--max-output", budget.max_output_gb,
                  "refuse runs estimated to write more frame data, GB");
}

void check_budget_flags(const chainmail::Budget& budget) {
  check_positive("--max-memory", budget.max_memory_gb);
  check_positive("--max-hours", budget.max_hours);
  check_positive("--max-output", budget.max_output_gb);
}

void add_run(CLI::App& app, RunFlags& flags) {
  chainmail::RunCommand& run = flags.command;
  CLI::App* sub = flags.app =
      app.add_subcommand("run", "run one scene through one or more backends");
  sub->add_option("scene", run.scene_file, "scene file (JSON)")->required();
  sub->add_option("--backends", flags.backends,
                  backends_help("backends to run") + " (default: those the scene names)");
  sub->add_option("--out", run.out_dir,
                  "output folder (default results/<scene name>/run); only a folder chainmail "
                  "made is replaced");
  sub->add_flag("--force", run.force, "replace an empty folder chainmail did not make");
  sub->add_option("--reference", run.reference,
                  "backend drape_rms is measured against (default: the scene's), or none");
  add_budget(sub, run.budget);
  sub->add_flag("--frames", run.frames, "write frames/<backend>/<NNNNN>.csv");
  sub->add_flag("--render", run.render, "render side-by-side PNG frames into images/");
  sub->add_flag("--report", run.report,
                "write index.html: tables, plots, images and the frames in 3D (chainmail report)");
  sub->add_option("--shader", run.shader,
                  "cloth shader for --render: blinn_phong, texture, bump, displacement, mirror")
      ->default_str("texture");
  sub->add_option("--material", run.material,
                  "ring material for --render: steel, silver, gold, copper, brass, bronze, "
                  "titanium")
      ->default_str("steel");
  sub->add_option("--export", run.exports,
                  "write every backend's frames as gltf (export/<backend>.glb) or npz "
                  "(export/<backend>.npz); repeat for both");
  sub->add_option("--set", run.overrides, "override a scene key: dotted.key=value")
      ->default_str("");
  sub->add_option("--cache", run.cache_dir,
                  "reference-run cache folder, or none (default ~/.cache/chainmail)");
  sub->add_flag("--quiet", flags.quiet, "no progress lines");
  add_threads(*sub, run.threads, "every hardware thread");
}

void add_sweep(CLI::App& app, SweepFlags& flags) {
  chainmail::SweepCommand& sweep = flags.command;
  CLI::App* sub = flags.app =
      app.add_subcommand("sweep", "error against run time over a grid of knob values");
  sub->add_option("scene", sweep.scene_file, "scene file (JSON)")->required();
  sub->add_option("--vary", sweep.vary, "KEY=v1,v2,... ({backend} in KEY: each backend)")
      ->default_str("")
      ->required();
  sub->add_option("--backends", flags.backends,
                  backends_help("backends") + " (default: those the scene names)");
  sub->add_option("--set", sweep.overrides, "override a scene key for every point")
      ->default_str("");
  sub->add_option("--out", sweep.out_dir, "output folder (default results/<scene>/sweep)");
  sub->add_flag("--force", sweep.force, "replace an empty folder chainmail did not make");
  sub->add_option("--jobs", sweep.jobs, "points run in parallel")->check(CLI::Range(1, 256));
  sub->add_flag("--print-jobs", sweep.print_jobs,
                "print the reference job, then each point's command line, and stop");
  sub->add_flag("--reference-only", sweep.reference_only,
                "run the reference into the cache and stop (the job --print-jobs prints first)");
  sub->add_option("--gather", sweep.gather,
                  "write DIR/sweep.csv and the plot from the points run into DIR/points by the "
                  "printed jobs or --slurm");
  sub->add_option("--slurm", sweep.slurm,
                  "write a script that submits the sweep to Slurm (reference, array, gather)");
  sub->add_option("--cache", sweep.cache_dir,
                  "reference-run cache folder, or none (default ~/.cache/chainmail)");
  add_threads(*sub, sweep.threads, "the hardware threads divided among --jobs");
}

void add_stability(CLI::App& app, StabilityFlags& flags) {
  chainmail::StabilityCommand& stability = flags.command;
  CLI::App* sub = flags.app =
      app.add_subcommand("stability", "stiff and extreme cases: verdicts and largest stable dt");
  sub->add_option("--backends", flags.backends, backends_help("backends"))->default_str("all");
  sub->add_option("--out", stability.out_dir, "output folder");
  sub->add_flag("--force", stability.force, "replace an empty folder chainmail did not make");
  sub->add_flag("--quick", stability.quick, "tiny sizes (test mode)");
  sub->add_option("--max-wall", stability.max_wall_seconds, "watchdog per run, s");
  add_threads(*sub, stability.threads, "every hardware thread");
}

void add_bench(CLI::App& app, BenchFlags& flags) {
  chainmail::BenchCommand& bench = flags.command;
  CLI::App* sub = flags.app = app.add_subcommand(
      "bench", "the default scene set across all backends, writing results/bench");
  sub->add_option("--out", bench.out_dir, "output folder");
  sub->add_flag("--force", bench.force, "replace an empty folder chainmail did not make");
  sub->add_flag("--quick", bench.quick, "reduced sizes and durations (test mode)");
  sub->add_option("--backends", flags.backends, backends_help("backends"))->default_str("all");
  sub->add_option("--jobs", bench.jobs, "sweep points in parallel")->check(CLI::Range(1, 256));
  sub->add_flag("--no-render", flags.no_render, "skip the side-by-side frames");
  sub->add_flag("--no-scaling", flags.no_scaling, "skip the scaling table");
  sub->add_option("--scaling-max", bench.scaling_max,
                  "largest sheet of the scaling table, rings a side (16 to 256)")
      ->check(CLI::Range(4, 256));
  add_threads(*sub, bench.threads, "every hardware thread; sweeps: divided among --jobs");
}

// the end of --help: exit statuses, and where the bench scenes are
std::string help_footer() {
  const chainmail::DataDir& data = chainmail::data_dir();
  return "Exit status: 0 ok, 1 a run was unstable, 2 bad input, 3 internal error, 4 the "
         "output could not be written, 130 interrupted.\n`chainmail backends` lists every backend "
         "and knob; the docs describe "
         "every scene key, flag, metric and output file.\nBench scenes: " +
         (data.root.empty() ? std::string("none found") : data.scenes()) +
         " (CHAINMAIL_DATA_DIR overrides the data folder).";
}

void add_info(CLI::App& app, InfoFlags& flags) {
  flags.backends = app.add_subcommand(
      "backends", "list every backend and each knob's type, default, range and meaning");
  flags.backends->add_flag("--json", flags.json, "as JSON (for tools)");
  chainmail::CheckCommand& check = flags.check_command;
  flags.check = app.add_subcommand(
      "check", "validate scene files as run would, and run nothing (exit 0: all valid, 2: not)");
  flags.check->add_option("scenes", check.scene_files, "scene files (JSON)")
      ->required()
      ->default_str("");
  flags.check->add_option("--set", check.overrides, "override a scene key: dotted.key=value")
      ->default_str("");
  flags.check->add_flag("--resolved", check.resolved,
                        "print each valid scene with every default filled in, one JSON line");
}

void add_render(CLI::App& app, RenderFlags& flags) {
  chainmail::RenderCommand& render = flags.command;
  CLI::App* sub = flags.app = app.add_subcommand(
      "render", "draw a saved run's frames again (run --frames), without simulating");
  sub->add_option("run", render.run_dir, "run folder with frames/")->required();
  sub->add_option("--backends", flags.backends, "panels, in this order (default: all with frames)");
  sub->add_option("--out", render.out_dir, "output folder (default results/<scene>/render)");
  sub->add_flag("--force", render.force, "replace an empty folder chainmail did not make");
  sub->add_option("--size", render.size, "panel size WxH, pixels (default 1280x720)");
  sub->add_option("--samples", render.samples,
                  "multisamples per pixel, 0 or 1 for none (default 4)")
      ->check(CLI::Range(0, 16));
  sub->add_option("--camera", render.camera,
                  "scene (default), auto, front, side, top, or X,Y,Z:X,Y,Z[:FOV_DEG] (position, "
                  "target, field of view)");
  sub->add_option("--fps", render.fps, "frame rate of --video (default 20)");
  sub->add_flag("--video", render.video, "also join the images into images/compare.mp4 (ffmpeg)");
  sub->add_option("--material", render.material,
                  "ring material: steel, silver, gold, copper, brass, bronze, titanium");
  sub->add_option("--shader", render.shader,
                  "cloth shader: blinn_phong, texture, bump, displacement, mirror");
  sub->add_option("--export", render.exports, "also export frames: gltf, npz (repeat for both)");
  sub->add_flag("--no-images", flags.no_images, "exports only (no GL needed)");
}

CLI::App* add_report(CLI::App& app, std::string& folder) {
  CLI::App* sub = app.add_subcommand(
      "report",
      "write index.html into a run, sweep, stability or bench folder: tables, plots, "
      "images and linked 3D views of every backend, viewable offline");
  sub->add_option("folder", folder, "the folder chainmail wrote")->required();
  return sub;
}

// the exit status when parsing ends the program (help, version, a parse error), else nullopt
std::optional<int> parse(CLI::App& app, int argc, char** argv) {
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
    return chainmail::kExitBadInput;
  }
  return std::nullopt;
}

// an --out given empty is a mistake, not a request for the default folder
void check_out_flag(const CLI::App* sub) {
  if (!*sub || !sub->count("--out")) return;
  const std::string out = sub->get_option("--out")->as<std::string>();
  if (out.find_first_not_of(" \t\r\n") == std::string::npos)
    throw UsageError("--out: an empty path");
}

int run_main(RunFlags& flags) {
  chainmail::RunCommand& run = flags.command;
  read_backends(flags.app, flags.backends, run.backends);
  if (!run.render && (flags.app->count("--shader") || flags.app->count("--material")))
    throw UsageError(std::string(flags.app->count("--shader") ? "--shader" : "--material") +
                     ": only with --render");
  check_budget_flags(run.budget);
  run.progress = !flags.quiet;
  return chainmail::run_command(run);
}

int sweep_main(SweepFlags& flags, const char* argv0) {
  read_backends(flags.app, flags.backends, flags.command.backends);
  // an empty --gather or --slurm path is a mistake, not a request for a default
  for (const char* flag : {"--gather", "--slurm"}) {
    if (!flags.app->count(flag)) continue;
    const std::string path = flags.app->get_option(flag)->as<std::string>();
    if (path.find_first_not_of(" \t\r\n") == std::string::npos)
      throw UsageError(std::string(flag) + ": an empty path");
  }
  flags.command.executable = self_path(argv0);
  return chainmail::sweep_command(flags.command);
}

int stability_main(StabilityFlags& flags) {
  read_backends(flags.app, flags.backends, flags.command.backends);
  check_positive("--max-wall", flags.command.max_wall_seconds);
  return chainmail::stability_command(flags.command);
}

int render_main(RenderFlags& flags) {
  read_backends(flags.app, flags.backends, flags.command.backends);
  flags.command.fps_given = flags.app->count("--fps") > 0;
  flags.command.images = !flags.no_images;
  return chainmail::render_command(flags.command);
}

int bench_main(BenchFlags& flags, const char* argv0) {
  read_backends(flags.app, flags.backends, flags.command.backends);
  flags.command.executable = self_path(argv0);
  flags.command.render = !flags.no_render;
  flags.command.scaling = !flags.no_scaling;
  return chainmail::bench_command(flags.command);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace chainmail;
  CLI::App app{"chainmail: a physics comparison harness for interlocking-ring fabric"};
  app.require_subcommand(1);
  app.option_defaults()->always_capture_default();  // --help shows every default
  app.set_version_flag("--version", chainmail_version() + " (" + chainmail_commit() + ", " +
                                        chainmail_build() + ")");
  RunFlags run_flags;
  SweepFlags sweep_flags;
  StabilityFlags stability_flags;
  BenchFlags bench_flags;
  RenderFlags render_flags;
  add_run(app, run_flags);
  add_sweep(app, sweep_flags);
  add_stability(app, stability_flags);
  add_bench(app, bench_flags);
  InfoFlags info_flags;
  add_info(app, info_flags);
  app.footer(help_footer());
  add_render(app, render_flags);
  std::string report_folder;
  const CLI::App* report_app = add_report(app, report_folder);
  if (const std::optional<int> status = parse(app, argc, argv)) return *status;

  install_interrupt_handlers();
  try {
    for (const CLI::App* sub :
         {run_flags.app, sweep_flags.app, stability_flags.app, bench_flags.app, render_flags.app})
      check_out_flag(sub);
    if (*run_flags.app) return run_main(run_flags);
    if (*sweep_flags.app) return sweep_main(sweep_flags, argv[0]);
    if (*stability_flags.app) return stability_main(stability_flags);
    if (*bench_flags.app) return bench_main(bench_flags, argv[0]);
    if (*info_flags.backends) return backends_command(info_flags.json);
    if (*info_flags.check) return check_command(info_flags.check_command);
    if (*render_flags.app) return render_main(render_flags);
    if (*report_app) return report_command(report_folder);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "chainmail: %s\n", e.what());
    return kExitBadInput;
  } catch (const SceneError& e) {
    std::fprintf(stderr, "chainmail: %s\n", e.what());
    return kExitBadInput;
  } catch (const OutputError& e) {
    std::fprintf(stderr, "chainmail: %s\n", e.what());
    return kExitOutput;
  } catch (const std::filesystem::filesystem_error& e) {
    if (!is_output_failure(e.code())) {
      std::fprintf(stderr, "chainmail: internal error: %s\n", e.what());
      return kExitInternal;
    }
    std::fprintf(stderr, "chainmail: cannot write %s: %s\n", e.path1().c_str(),
                 e.code().message().c_str());
    return kExitOutput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainmail: internal error: %s\n", e.what());
    return kExitInternal;
  }
  return kExitOk;
}

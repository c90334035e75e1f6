#include "bench/harness/suites/bench_suite.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <sstream>

#include "backends/backend.hpp"
#include "bench/harness/commands/commands.hpp"
#include "bench/harness/common/data_dir.hpp"
#include "bench/harness/common/interrupt.hpp"
#include "bench/harness/output/number_format.hpp"
#include "bench/harness/output/output.hpp"
#include "bench/harness/output/output_folder.hpp"
#include "bench/harness/output/render_output.hpp"
#include "bench/harness/output/table_cells.hpp"
#include "bench/harness/report/report.hpp"
#include "bench/harness/run/run.hpp"
#include "bench/harness/suites/scaling.hpp"
#include "bench/harness/suites/stability.hpp"
#include "bench/harness/suites/sweep.hpp"
#include "bench/harness/suites/timed_rounds.hpp"
#include "core/parallel.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace fs = std::filesystem;

const BenchPlan& bench_plan() {
  const std::vector<std::string> quick_sheet = {"weave.rows=4", "weave.cols=4", "duration=0.05"};
  static const BenchPlan plan{
      // sizes for a bench of a few minutes on 2 cores (the rigid backends cost the most): 16 x 16
      // sheets (the paper's 30 x 30 is measured by `chainmail run` on the scene files themselves),
      // with cameras moved in to frame the smaller sheets
      .scenes =
          {
              {"curtain.json",
               {"weave.rows=16", "weave.cols=16", "duration=1.0", "camera.position=[0.03,0.31,0.2]",
                "camera.target=[0,0.295,0]"},
               quick_sheet,
               /*frames=*/true},
              {"corner_hang.json", {"duration=1.0"}, quick_sheet},
              {"table_cloth.json",
               {"weave.rows=16", "weave.cols=16", "duration=1.0", "colliders.0.radius=0.03",
                "support.radius=0.03", "camera.position=[0.06,0.16,0.17]",
                "camera.target=[0,0.06,0]"},
               quick_sheet},
              {"sphere_drape.json",
               {"weave.rows=16", "weave.cols=16", "duration=1.0", "colliders.0.radius=0.03",
                "colliders.0.center=[0,0.12,0]", "camera.position=[0.07,0.19,0.17]",
                "camera.target=[0,0.1,0]"},
               quick_sheet,
               /*frames=*/true},
              {"chain_catenary.json", {}, {"weave.cols=8", "duration=0.05"}},
              {"chain_pile.json",
               {"weave.cols=40", "duration=1.0"},
               {"weave.cols=6", "duration=0.05"}},
          },
      // error against run time, every bench scene over each backend's dt (8 x 8 sheets, about 5
      // cm: the table and the ball shrink to 1.5 cm so that the cloth drapes over them; shorter
      // chains)
      .sweeps =
          {
              {"curtain.json", {"weave.rows=8", "weave.cols=8", "duration=0.5"}, quick_sheet},
              {"corner_hang.json", {"weave.rows=8", "weave.cols=8", "duration=0.5"}, quick_sheet},
              {"table_cloth.json",
               {"weave.rows=8", "weave.cols=8", "duration=0.5", "colliders.0.radius=0.015",
                "support.radius=0.015"},
               quick_sheet},
              {"sphere_drape.json",
               {"weave.rows=8", "weave.cols=8", "duration=0.5", "colliders.0.radius=0.015",
                "colliders.0.center=[0,0.12,0]"},
               quick_sheet},
              {"chain_catenary.json",
               {"weave.cols=30", "duration=2.0"},
               {"weave.cols=8", "duration=0.05"}},
              {"chain_pile.json",
               {"weave.cols=20", "duration=0.5"},
               {"weave.cols=6", "duration=0.05"}},
          },
      .vary = "backends.{backend}.dt=0.008,0.004,0.002,0.001,0.0005",
      .quick_vary = "backends.{backend}.dt=0.004,0.002",
      .stability_watchdog_s = 10.0,
      .quick_stability_watchdog_s = 5.0,
      .timing_runs = 3,
      .quick_timing_runs = 2,
      // ODE's 16 x 16 sheets step for 7 to 19 s a run on 2 shared cores: each is repeated, as
      // ODE is what every row's cost vs ODE divides by (Bullet's, 55 to 90 s, run once)
      .timing_repeat_budget_s = 20.0,
  };
  return plan;
}

namespace {

using RenderWriter = std::function<void(const SceneRun&, const std::string&)>;

// what the bench's steps share
struct BenchRun {
  const BenchCommand& command;
  const BenchPlan& plan;
  std::string scenes;   // the scene folder
  std::string out;      // the staging folder
  std::string cache;    // reference runs, inside `out`
  RenderWriter render;  // empty: no images

  std::vector<std::string> backends() const {
    return command.backends.empty() ? std::vector<std::string>{kAllBackends} : command.backends;
  }
};

// the final frame of every backend side by side (quick_sheet), when rendering is available
RenderWriter bench_renderer(const BenchCommand& command) {
  if (!command.render) return {};
  try {
    return make_render_writer("", "", /*last_only=*/true);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench: no frames rendered (%s)\n", e.what());
    return {};
  }
}

// timing.md, timing.csv and metrics.md as they fill
struct BenchTables {
  std::ostringstream timing, timing_csv, metrics;
};

void start_tables(BenchTables& t, double timing_repeat_budget_s) {
  t.timing << "# Timing\n\nms per step (wall time inside `step()` only), real-time factor "
              "(simulated / wall seconds) and cost per simulated second relative to `plausible` "
              "and to `ode`. A backend whose run spent at most "
           << table_number(timing_repeat_budget_s, 3)
           << " s in `step()` runs again (`runs` in all, those of a scene taken in turn over the "
              "backends) and its row gives the median run; the first run wrote the scene's "
              "frames and metrics. A row marked `hash differs` ended on another final state in "
              "a later run.\n\n"
              "| scene | rings | backend | dt (s) | ms/step | real-time factor | cost vs "
              "plausible | cost vs ODE | runs | verdict |\n"
              "|---|---|---|---|---|---|---|---|---|---|\n";
  t.timing_csv << "scene,rings,backend,dt,steps,ms_per_step,realtime_factor,verdict,hash,runs,"
                  "hashes_agree,cost_vs_ode\n";
  t.metrics << "# Final metrics\n\n`drape_rms` against each scene's reference backend (mm); "
               "`catenary` is the chain's sag error against the analytic catenary; depths are the "
               "deepest and mean interpenetration of linked (and of other) pairs in wire radii a; "
               "settled: kinetic energy at the end below "
            << table_number(100.0 * kSettledEnergyFraction, 3)
            << " % of the energy released; overstretched: a link stretched above "
            << table_number(1.0 + kOverstretchTolerance, 4)
            << " (impossible for real rings).\n\n"
               "| scene | backend | verdict | settled | overstretched | max_stretch | "
               "mean_stretch | penetrating_linked | depth max/mean linked (a) | "
               "penetrating_other | depth max/mean other (a) | broken_links | false_links | "
               "drape_rms (mm) | drape_coefficient | catenary |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
}

// the timing table's rows of one scene: each backend's run, and, when it stepped for at most the
// budget, more runs of it taken in rounds over the backends; its wall time becomes the median's
struct TimingRows {
  std::vector<BackendRun> runs;  // as run.runs, wall_s the median run's
  std::vector<int> counts;       // runs of each
  std::vector<bool> hashes_agree;
};

TimingRows timing_rows(const SceneRun& run, int threads, int runs, double budget_s, bool progress) {
  TimingRows rows{run.runs, std::vector<int>(run.runs.size(), 1),
                  std::vector<bool>(run.runs.size(), true)};
  std::vector<TimedEntry> again;
  std::vector<std::size_t> row_of;
  for (std::size_t k = 0; k < run.runs.size(); ++k) {
    const BackendRun& r = run.runs[k];
    const BackendInfo* info = find_backend(r.name);
    if (runs <= 1 || !info || r.steps == 0 || r.wall_s > budget_s) continue;
    again.push_back({r.name, info->multithreaded ? threads : 1, runs - 1, 1});
    row_of.push_back(k);
  }
  const std::vector<TimedResult> results =
      run_in_rounds(run.scene, again, "timing", run.scene.name, progress);
  for (std::size_t e = 0; e < again.size(); ++e) {
    BackendRun& row = rows.runs[row_of[e]];
    std::vector<double> ms = results[e].ms_per_step;
    const bool agree = results[e].hashes_agree && (ms.empty() || results[e].last.hash == row.hash);
    ms.push_back(row.ms_per_step());
    row.wall_s = 1e-3 * median_of(ms) * static_cast<double>(row.steps);
    rows.counts[row_of[e]] = static_cast<int>(ms.size());
    rows.hashes_agree[row_of[e]] = agree;
  }
  return rows;
}

// one scene's rows of the timing and metric tables
void add_rows(BenchTables& t, const SceneRun& run, const TimingRows& timing) {
  const Scene& scene = run.scene;
  const double plausible = plausible_cost(timing.runs), ode = backend_cost(timing.runs, "ode");
  for (std::size_t k = 0; k < timing.runs.size(); ++k) {
    const BackendRun& r = timing.runs[k];
    const bool agree = timing.hashes_agree[k];
    t.timing << "| " << scene.name << " | " << run.weave.size() << " | " << r.name << " | "
             << timing_cells(r, plausible) << " | " << relative_cost_cell(r, ode) << " | "
             << timing.counts[k] << " | " << to_string(r.verdict) << (agree ? "" : ", hash differs")
             << " |\n";
    t.timing_csv << scene.name << ',' << run.weave.size() << ',' << r.name << ','
                 << csv_number(r.dt) << ',' << r.steps << ',' << csv_number(r.ms_per_step()) << ','
                 << csv_number(r.realtime_factor()) << ',' << to_string(r.verdict) << ','
                 << std::hex << r.hash << std::dec << ',' << timing.counts[k] << ','
                 << (agree ? "true" : "false") << ',';
    if (const double vs_ode = relative_cost(r, ode); !std::isnan(vs_ode))
      t.timing_csv << csv_number(vs_ode);
    t.timing_csv << '\n';
  }
  for (const auto& r : run.runs) {
    t.metrics << "| " << scene.name << " | " << r.name << " | " << to_string(r.verdict) << " | "
              << yes_no_cell(r.settled) << " | " << yes_no_cell(r.overstretched) << " | "
              << (r.started() ? final_metric_cells(r.final_metrics(), scene.ring.wire_radius)
                              : missing_metric_cells())
              << " | " << catenary_cell(r.catenary_error) << " |\n";
  }
}

// every scene of the plan through every backend: its run folder and its table rows
void run_scenes(const BenchRun& bench) {
  const bool quick = bench.command.quick;
  BenchTables tables;
  start_tables(tables, bench.plan.timing_repeat_budget_s);
  for (const BenchStep& step : bench.plan.scenes) {
    if (interrupted()) break;
    const Scene scene =
        load_scene_file(bench.scenes + step.file, step.overrides(bench.command.quick));
    RunOptions options;
    options.backends = bench.backends();
    options.progress = bench.command.progress;
    options.cache_dir = bench.cache;
    options.threads = bench.command.threads > 0 ? bench.command.threads : hardware_threads();
    options.folder = bench.out + "/" + scene.name;
    options.keep_stream = static_cast<bool>(bench.render);
    options.frame_csv = step.frames;  // outside step(): the timing does not see it
    const SceneRun run = run_scene(scene, options);
    OutputOptions output;
    output.render = bench.render;
    write_run_folder(run, options.folder, output);
    // (after a Ctrl-C the rows keep the one run: no more are taken)
    const TimingRows timing = timing_rows(
        run, options.threads, quick ? bench.plan.quick_timing_runs : bench.plan.timing_runs,
        bench.plan.timing_repeat_budget_s, bench.command.progress);
    add_rows(tables, run, timing);
  }
  write_file_atomic(bench.out + "/timing.md", tables.timing.str());
  write_file_atomic(bench.out + "/timing.csv", tables.timing_csv.str());
  write_file_atomic(bench.out + "/metrics.md", tables.metrics.str());
}

// the plan's sweeps, each into sweep/<scene>/
void run_sweeps(const BenchRun& bench) {
  const bool quick = bench.command.quick;
  for (const BenchStep& step : bench.plan.sweeps) {
    if (interrupted()) break;
    SweepCommand sweep;
    sweep.scene_file = bench.scenes + step.file;
    sweep.overrides = step.overrides(quick);
    sweep.vary = {quick ? bench.plan.quick_vary : bench.plan.vary};
    sweep.backends = bench.backends();
    sweep.out_dir = bench.out + "/sweep/" + fs::path(step.file).stem().string();
    sweep.jobs = bench.command.jobs;
    sweep.threads = bench.command.threads;
    sweep.executable = bench.command.executable;
    sweep.progress = bench.command.progress;
    sweep.cache_dir = bench.cache;
    sweep_command(sweep);
  }
}

// the stiff and extreme cases into stability/
void run_stability(const BenchRun& bench) {
  const bool quick = bench.command.quick;
  StabilityCommand stability;
  stability.backends = bench.command.backends;
  stability.out_dir = bench.out + "/stability";
  stability.quick = quick;
  stability.max_wall_seconds =
      quick ? bench.plan.quick_stability_watchdog_s : bench.plan.stability_watchdog_s;
  stability.progress = bench.command.progress;
  stability_command(stability);
}

std::string bench_readme(double minutes) {
  std::ostringstream readme;
  readme
      << "# Results of `chainmail bench`\n\n"
         "Regenerate with `./scripts/bench.sh` (or `chainmail bench --out results/bench`). Every "
         "scene "
         "runs through every backend from the same rest layout; numbers below come from one "
         "run on the machine that produced them (2 cores), so compare ratios, not absolutes.\n\n"
         "- `timing.md` / `timing.csv` — ms per step, real-time factor, cost relative to "
         "`plausible` and to `ode`, verdict and final-frame hash for each scene and backend; "
         "the median of 3 runs taken in turn where a run takes at most about 12 s.\n"
         "- `metrics.md` — final metrics: stretch (centre distance / inner diameter; above 1 is "
         "impossible for real rings), interpenetrating pairs among neighbours and others, broken "
         "and false links, drape error against the reference backend, Cusick drape coefficient "
         "(table_cloth), catenary sag error (chain_catenary).\n"
         "- `<scene>/` — each scene's `summary.json`, `metrics.csv` (every sample), `table.md` and "
         "`images/` (the final frame of every backend side by side, when rendering is available); "
         "`curtain/` and `sphere_drape/` keep `frames/` too, every sample of every backend.\n"
         "- `index.html` — every table, plot and image here on one page, opened from disk, with "
         "the curtain and the sphere drape in 3D (every backend side by side).\n"
         "- `scaling.md` / `scaling.csv` / `scaling.png` — the curtain at 16 to 256 rings a side: "
         "ms per step of plausible on 1 and 2 threads (median of 5 runs), speed-up, cost per ring "
         "per step, max_stretch and whether the final hash is the same on any thread count; the "
         "other backends up to the size they finish within a minute (median of 3 runs where a "
         "run takes at most about 12 s), with each one's cost relative to ODE's; the runs at a "
         "size taken in turn.\n"
         "- `sweep/<scene>/` — error against run time, the Pareto front across models: every "
         "bench scene (sheets of 8 x 8, shorter chains) at a range of dt per backend; `sweep.csv` "
         "(wall seconds per simulated second, drape error against the reference run) and "
         "`sweep.png` (log-log, the front marked: which model to pick for an error budget).\n"
         "- `stability/` — the stiff and extreme cases: verdict at default settings and the "
         "largest stable dt found by bisection.\n"
         "- `stability/` is written last; the gallery (`../curtain_30x30/`), the shader "
         "pictures (`../shaders/`) and the renderer benchmark (`../micro_render.csv`) come from "
         "their own scripts, not from `bench`.\n";
  char took[96];
  std::snprintf(took, sizeof took, "\nThis bench took %.1f minutes.\n", minutes);
  readme << took;
  if (interrupted()) readme << "\nInterrupted: only what finished is here.\n";
  return readme.str();
}

}  // namespace

int bench_command(const BenchCommand& command) {
  const auto started = std::chrono::steady_clock::now();
  const BenchPlan& plan = bench_plan();
  const std::string scenes = data_dir().scenes() + "/";
  // bad names are bad input before anything runs or is written
  if (!command.backends.empty())
    select_backends(load_scene_file(scenes + plan.scenes[0].file), command.backends);
  OutputFolder folder = OutputFolder::claim(command.out_dir, "bench", command.force);
  // reference runs are cached by scene, knobs and build; a bench still starts with a cache of its
  // own (inside its staging folder, gone when it is done) so it measures every reference afresh
  const BenchRun bench{command,
                       plan,
                       scenes,
                       folder.staging(),
                       folder.staging() + "/.cache",
                       bench_renderer(command)};

  run_scenes(bench);
  if (command.scaling && !interrupted()) {
    const ScalingPlan scaling = scaling_plan(command.quick, command.scaling_max);
    const std::string table =
        run_scaling(scaling, scenes, bench.backends(), bench.out, command.progress);
    write_file_atomic(bench.out + "/scaling.md", "# Scaling\n\n" + table);
  }
  run_sweeps(bench);
  if (!interrupted()) run_stability(bench);

  const double minutes =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() / 60.0;
  write_file_atomic(bench.out + "/README.md", bench_readme(minutes));
  std::error_code ignored;
  fs::remove_all(bench.cache, ignored);
  write_report_beside(folder.staging(), "bench");  // index.html: the front page of the results
  folder.commit();
  std::fprintf(stderr, "bench: wrote %s in %.1f min%s\n", command.out_dir.c_str(), minutes,
               interrupted() ? " (interrupted)" : "");
  // instabilities are findings written to the tables, not a failed bench
  return interrupted() ? kExitInterrupted : kExitOk;
}

}  // namespace chainmail

#include "bench/harness/suites/scaling.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <sstream>

#include "backends/backend.hpp"
#include "bench/harness/common/interrupt.hpp"
#include "bench/harness/output/number_format.hpp"
#include "bench/harness/output/output.hpp"
#include "bench/harness/run/run.hpp"
#include "bench/harness/run/verdict.hpp"
#include "bench/harness/suites/process.hpp"
#include "bench/harness/suites/timed_rounds.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace {

// one cell of the table: a backend at a size on some threads
struct ScalingCell {
  std::string backend;
  int side = 0, rings = 0, threads = 1, runs = 0;
  long long steps = 0;
  double ms_per_step = 0.0;  // median over the runs
  double dt = 0.0;           // s
  double max_stretch = 0.0;  // largest over the run (peak_stretch)
  std::string verdict;
  std::uint64_t hash = 0;
  bool hashes_agree = true;  // every run of this cell ended on the same hash
};

Scene curtain_at(const ScalingPlan& plan, const std::string& scenes, int side) {
  const std::string d = csv_number(plan.duration);
  return load_scene_file(scenes + "/curtain.json", {"weave.rows=" + std::to_string(side),
                                                    "weave.cols=" + std::to_string(side),
                                                    "duration=" + d, "sample_interval=" + d});
}

// what one size measures of one backend: a cell per thread count, each the median of `repeats`
// runs
struct ScalingEntry {
  std::string backend;
  std::vector<int> thread_counts;
  int repeats = 1;
};

// a TimedEntry per entry and thread count, in the order the cells are listed
std::vector<TimedEntry> timed_entries(const std::vector<ScalingEntry>& entries) {
  std::vector<TimedEntry> timed;
  for (const ScalingEntry& entry : entries)
    for (int threads : entry.thread_counts)
      timed.push_back({entry.backend, threads, entry.repeats});
  return timed;
}

// the cells of one size from its runs
std::vector<ScalingCell> cells_of(const Scene& scene, const std::vector<TimedEntry>& timed,
                                  const std::vector<TimedResult>& results) {
  std::vector<ScalingCell> cells;
  for (std::size_t k = 0; k < timed.size(); ++k) {
    ScalingCell cell;
    cell.backend = timed[k].backend;
    cell.side = scene.weave.cols;
    cell.rings = scene.weave.rows * scene.weave.cols;
    cell.threads = timed[k].threads;
    const TimedResult& result = results[k];
    cell.runs = static_cast<int>(result.ms_per_step.size());
    if (cell.runs == 0) continue;  // stopped (Ctrl-C) before its first run
    cell.ms_per_step = median_of(result.ms_per_step);
    cell.hash = result.last.hash;
    cell.hashes_agree = result.hashes_agree;
    cell.steps = result.last.steps;
    cell.dt = result.last.dt;
    cell.max_stretch = result.last.peak_stretch;
    cell.verdict = to_string(result.last.verdict);
    cells.push_back(cell);
  }
  return cells;
}

// a cell's cost per simulated second over ODE's on one thread at the same size (0: none measured)
double cost_vs_ode(const ScalingCell& cell, const std::vector<ScalingCell>& cells) {
  for (const ScalingCell& ode : cells) {
    if (ode.backend == "ode" && ode.side == cell.side && ode.threads == 1 &&
        ode.ms_per_step > 0.0 && cell.dt > 0.0)
      return (cell.ms_per_step / cell.dt) / (ode.ms_per_step / ode.dt);
  }
  return 0.0;
}

// wall seconds a run of `info` is estimated to take (the registry's rough cost)
double estimated_seconds(const BackendInfo& info, const Scene& scene, double dt) {
  const double steps = scene.duration / dt;
  return 1e-6 * info.cost_us_per_ring_step * scene.weave.rows * scene.weave.cols * steps;
}

std::string hex(std::uint64_t value) {
  char text[20];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

void write_csv(const std::vector<ScalingCell>& cells, const std::string& path) {
  std::ostringstream csv;
  csv << "backend,side,rings,threads,runs,steps,dt,ms_per_step,us_per_ring_step,"
         "realtime_factor,speedup,max_stretch,verdict,hash,hashes_agree,cost_vs_ode\n";
  for (const ScalingCell& c : cells) {
    // the speed-up over the same backend and size on one thread
    std::string speedup;
    for (const ScalingCell& one : cells) {
      if (one.backend == c.backend && one.side == c.side && one.threads == 1 && c.threads > 1 &&
          c.ms_per_step > 0.0)
        speedup = csv_number(one.ms_per_step / c.ms_per_step);
    }
    csv << c.backend << ',' << c.side << ',' << c.rings << ',' << c.threads << ',' << c.runs << ','
        << c.steps << ',' << csv_number(c.dt) << ',' << csv_number(c.ms_per_step) << ','
        << csv_number(1e3 * c.ms_per_step / c.rings) << ','
        << csv_number(c.ms_per_step > 0.0 ? 1e3 * c.dt / c.ms_per_step : 0.0) << ',' << speedup
        << ',' << csv_number(c.max_stretch) << ',' << c.verdict << ',' << hex(c.hash) << ','
        << (c.hashes_agree ? "true" : "false") << ',';
    const double vs_ode = cost_vs_ode(c, cells);
    if (vs_ode > 0.0) csv << csv_number(vs_ode);
    csv << '\n';
  }
  write_file_atomic(path, csv.str());
}

std::string markdown(const std::vector<ScalingCell>& cells, const ScalingPlan& plan) {
  std::ostringstream md;
  char line[1024];
  std::snprintf(line, sizeof line,
                "The curtain (4-in-1, hung from its top edge, self-contact on, each "
                "backend's default dt) for %.2g s at each size; ms per step counts `step()` only, "
                "the median of the runs (%d for plausible, %d for every other backend whose run "
                "is estimated to take at most %.3g s, one otherwise), on 1 and 2 threads where the "
                "backend steps on several; the runs go round the sizes, and at each size round the "
                "backends and thread counts, so a slow spell of the machine falls on all of them. "
                "Cost vs ODE: cost per simulated second over ODE's on one thread at that size. "
                "Same hash: every "
                "run of the backend at that size, on any thread count, ended on the same "
                "final-state hash.\n\n",
                plan.duration, plan.plausible_repeats, plan.repeats, plan.repeat_budget_s);
  md << line
     << "| backend | rings | threads | runs | ms/step | µs per ring-step | real-time factor | "
        "speed-up | cost vs ODE | max_stretch | same hash |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ScalingCell& c : cells) {
    double one = 0.0;
    for (const ScalingCell& o : cells)
      if (o.backend == c.backend && o.side == c.side && o.threads == 1) one = o.ms_per_step;
    bool same = c.hashes_agree;
    for (const ScalingCell& o : cells)
      if (o.backend == c.backend && o.side == c.side) same = same && o.hash == c.hash;
    char speedup[32] = "";
    if (c.threads > 1 && c.ms_per_step > 0.0)
      std::snprintf(speedup, sizeof speedup, "%.2f×", one / c.ms_per_step);
    char vs_ode[32] = "";
    if (const double cost = cost_vs_ode(c, cells); cost > 0.0)
      std::snprintf(vs_ode, sizeof vs_ode, "%.3g", cost);
    std::snprintf(line, sizeof line,
                  "| %s | %d × %d | %d | %d | %.3f | %.3f | %.3g | %s | %s | %.4f | %s |\n",
                  c.backend.c_str(), c.side, c.side, c.threads, c.runs, c.ms_per_step,
                  1e3 * c.ms_per_step / c.rings, 1e3 * c.dt / std::max(c.ms_per_step, 1e-12),
                  speedup, vs_ode, c.max_stretch, same ? "yes" : "no");
    md << line;
  }
  md << "\n`scaling.csv` holds the same cells; `scaling.png` plots ms per step against rings "
        "(log-log) with the O(n) line through plausible's 32 × 32 point.\n";
  return md.str();
}

}  // namespace

ScalingPlan scaling_plan(bool quick, int max_side) {
  ScalingPlan plan;
  plan.threads = {1, 2};
  if (quick) {
    plan.sides = {4, 8};
    plan.duration = 0.02;
    plan.repeats = 1;
    plan.plausible_repeats = 1;
    plan.budget_s = 5.0;
  } else {
    plan.sides = {16, 32, 64, 128, 256};
  }
  std::erase_if(plan.sides, [&](int side) { return side > max_side; });
  return plan;
}

// the backends' entries at one size: plausible always, the others within the plan's budget
std::vector<ScalingEntry> scaling_entries(const ScalingPlan& plan, const Scene& scene,
                                          const std::vector<std::string>& backends) {
  std::vector<ScalingEntry> entries;
  for (const std::string& name : select_backends(scene, backends)) {
    const BackendInfo& info = *find_backend(name);
    const bool plausible = name == "plausible";
    const double estimate = estimated_seconds(info, scene, resolve_knobs(scene, info).at("dt"));
    if (!plausible && estimate > plan.budget_s) continue;
    entries.push_back({name, info.multithreaded ? plan.threads : std::vector<int>{1},
                       plausible                          ? plan.plausible_repeats
                       : estimate <= plan.repeat_budget_s ? plan.repeats
                                                          : 1});
  }
  return entries;
}

std::string run_scaling(const ScalingPlan& plan, const std::string& scenes_dir,
                        const std::vector<std::string>& backends, const std::string& out,
                        bool progress) {
  // every size's runs taken in rounds together (16, 32, ... 256, then again), each size's
  // entries in turn (1, 2 threads; plausible, ode, torus_xpbd, ...): a slow spell of the machine
  // falls on every size and backend alike, so the ratios between sizes compare like with like
  std::vector<Scene> scenes;
  for (int side : plan.sides) scenes.push_back(curtain_at(plan, scenes_dir, side));
  std::vector<SceneEntries> groups;
  for (const Scene& scene : scenes) {
    const std::string side = std::to_string(scene.weave.cols);
    groups.push_back(
        {&scene, side + " x " + side, timed_entries(scaling_entries(plan, scene, backends))});
  }
  const std::vector<std::vector<TimedResult>> results = run_in_rounds(groups, "scaling", progress);
  std::vector<ScalingCell> cells;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const std::vector<ScalingCell> measured = cells_of(scenes[g], groups[g].entries, results[g]);
    cells.insert(cells.end(), measured.begin(), measured.end());
  }
  write_csv(cells, out + "/scaling.csv");
  make_plot("plot_scaling.py", {out + "/scaling.csv", out + "/scaling.png"});
  return markdown(cells, plan);
}

}  // namespace chainmail

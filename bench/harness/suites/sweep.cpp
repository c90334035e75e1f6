#include "bench/harness/suites/sweep.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "backends/backend.hpp"
#include "bench/harness/commands/commands.hpp"
#include "bench/harness/common/interrupt.hpp"
#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/output/number_format.hpp"
#include "bench/harness/output/output.hpp"
#include "bench/harness/output/output_folder.hpp"
#include "bench/harness/run/budget.hpp"
#include "bench/harness/run/run.hpp"
#include "bench/harness/suites/process.hpp"
#include "bench/harness/suites/sweep_jobs.hpp"
#include "core/parallel.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace fs = std::filesystem;
using json = nlohmann::json;

double reference_run_dt(double scene_reference_dt, double scene_dt,
                        const std::vector<double>& swept_dts) {
  if (scene_reference_dt > 0.0) return scene_reference_dt;
  double dt = scene_dt;
  for (double swept : swept_dts) dt = std::min(dt, swept);
  return dt;
}

int sweep_threads(const SweepCommand& command) {
  if (command.threads > 0) return command.threads;
  return std::max(1, hardware_threads() / std::max(1, command.jobs));
}

std::vector<std::string> SweepJobs::args(const SweepPoint& p, size_t k,
                                         const std::string& folder) const {
  std::vector<std::string> args = {executable,
                                   "run",
                                   scene_file,
                                   "--backends",
                                   p.backend,
                                   "--out",
                                   folder + "/points/" + std::to_string(k),
                                   "--cache",
                                   cache.empty() ? "none" : cache,
                                   "--threads",
                                   std::to_string(threads),
                                   "--quiet"};
  for (const auto& s : overrides) args.insert(args.end(), {"--set", s});
  for (const auto& s : p.sets) args.insert(args.end(), {"--set", s});
  args.insert(args.end(), {"--set", reference_set});
  return args;
}

std::vector<std::string> sweep_args(const SweepCommand& command, const SweepJobs& jobs,
                                    const std::vector<std::string>& extra) {
  std::vector<std::string> args = {jobs.executable, "sweep", jobs.scene_file};
  for (const auto& v : command.vary) args.insert(args.end(), {"--vary", v});
  std::string backends;
  for (const auto& b : command.backends) backends += (backends.empty() ? "" : ",") + b;
  if (!backends.empty()) args.insert(args.end(), {"--backends", backends});
  for (const auto& s : command.overrides) args.insert(args.end(), {"--set", s});
  args.insert(args.end(), {"--cache", jobs.cache.empty() ? "none" : jobs.cache});
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

std::string command_line(const std::vector<std::string>& args) {
  std::string line;
  for (const auto& a : args) {
    if (!line.empty()) line += ' ';
    line += shell_quote(a);
  }
  return line;
}

namespace {

// each point's scene checked before anything runs (a bad value is bad input); returns each
// point's time step for its own backend, s
std::vector<double> check_points(const SweepCommand& command,
                                 const std::vector<SweepPoint>& points) {
  std::vector<double> dts;
  for (const SweepPoint& p : points) {
    std::vector<std::string> sets = command.overrides;
    sets.insert(sets.end(), p.sets.begin(), p.sets.end());
    const Scene scene = load_scene_file(command.scene_file, sets);
    validate_backend_knobs(scene);
    check_budget(scene, estimate_run(scene, {p.backend}, 0.0), Budget{});
    dts.push_back(resolve_knobs(scene, *find_backend(p.backend)).at("dt"));
  }
  return dts;
}

// every point is measured against one reference run, whatever the point's knobs
double sweep_reference_dt(const Scene& base, const std::vector<SweepPoint>& points,
                          const std::vector<double>& dts) {
  std::vector<double> swept;
  for (size_t k = 0; k < points.size(); ++k) {
    if (points[k].backend == base.reference) swept.push_back(dts[k]);
  }
  const BackendInfo* reference = find_backend(base.reference);
  const double scene_dt = reference ? resolve_knobs(base, *reference).at("dt") : 0.0;
  return reference_run_dt(base.reference_dt, scene_dt, swept);
}

// the reference job first (with a cache: the points read it from there), then one line per point
void print_jobs(const SweepCommand& command, const SweepPlan& plan) {
  if (!plan.jobs.cache.empty())
    std::printf("%s\n", command_line(sweep_args(command, plan.jobs, {"--reference-only"})).c_str());
  for (size_t k = 0; k < plan.points.size(); ++k)
    std::printf("%s\n", command_line(plan.jobs.args(plan.points[k], k, plan.out)).c_str());
}

// the reference run once, before the points share it through the cache
void cache_reference(const SweepCommand& command, const SweepJobs& jobs) {
  RunOptions options;
  options.progress = command.progress;
  options.cache_dir = jobs.cache;
  options.threads = jobs.threads;
  std::vector<std::string> sets = command.overrides;
  sets.push_back(jobs.reference_set);
  const Scene scene = load_scene_file(command.scene_file, sets);
  if (!jobs.cache.empty() && !interrupted())
    ensure_reference_cached(scene, scene.reference, options);
}

void run_points(const SweepCommand& command, const SweepJobs& jobs,
                const std::vector<SweepPoint>& points, const std::string& staging) {
  fs::create_directories(staging + "/points");
  std::mutex print;
  std::atomic<int> done{0};
  run_parallel(static_cast<int>(points.size()), command.jobs, [&](int k) {
    if (interrupted()) return;
    run_child(jobs.args(points[k], k, staging), staging + "/points/" + std::to_string(k) + ".log");
    std::lock_guard<std::mutex> lock(print);
    if (command.progress) std::fprintf(stderr, "  sweep point %d / %zu\n", ++done, points.size());
  });
}

// one row of sweep.csv from the point's summary.json; false when it did not end stable
bool sweep_row(const SweepPoint& p, const std::string& summary_file, std::ostringstream& csv) {
  csv << p.backend;
  for (const auto& v : p.values) csv << ',' << v;
  std::ifstream in(summary_file);
  json summary = json::parse(in, nullptr, false);
  if (summary.is_discarded() || !summary["backends"].contains(p.backend)) {
    csv << ",,,,,false," << (interrupted() ? "interrupted" : "error") << "\n";
    return false;
  }
  const json& b = summary["backends"][p.backend];
  auto number = [](const json& v) { return v.is_number() ? v.get<double>() : NAN; };
  // cost per simulated second of what was simulated: an unstable run stops early
  const double simulated = number(b["steps"]) * number(b["dt"]);
  const double duration = simulated > 0.0 ? simulated : number(summary["scene"]["duration"]);
  const double error = b["final"].contains("drape_rms") ? number(b["final"]["drape_rms"]) : NAN;
  const double cat = b.contains("catenary_error") ? number(b["catenary_error"]) : NAN;
  csv << ',' << csv_number(number(b["wall_s"]) / duration) << ','
      << csv_number(number(b["ms_per_step"])) << ',' << csv_number(error) << ',' << csv_number(cat)
      << ',' << (b["stable"].get<bool>() ? "true" : "false") << ','
      << b["verdict"].get<std::string>() << '\n';
  return b["stable"].get<bool>();
}

}  // namespace

int write_sweep_csv(const std::vector<SweepAxis>& axes, const std::vector<SweepPoint>& points,
                    const std::string& staging) {
  std::ostringstream csv;
  csv << "backend";
  for (const auto& axis : axes) csv << ',' << axis.key;
  csv << ",wall_per_sim_s,ms_per_step,error_m,catenary_error,stable,verdict\n";
  int unstable = 0;
  for (size_t k = 0; k < points.size(); ++k) {
    const std::string summary = staging + "/points/" + std::to_string(k) + "/summary.json";
    unstable += !sweep_row(points[k], summary, csv);
  }
  write_file_atomic(staging + "/sweep.csv", csv.str());
  return unstable;
}

namespace {

// every point is measured against one reference run, made with the reference backend's knobs as
// the scene gives them. A point that varies one of those knobs (other than dt, which the reference
// run sets itself) would make its own reference run with the same knob: it would be measured
// against itself, an error of 0 that means nothing
void refuse_varied_reference(const Scene& base, const std::vector<SweepPoint>& points) {
  const std::string prefix = "backends." + base.reference + ".";
  for (const SweepPoint& point : points) {
    if (point.backend != base.reference) continue;
    for (const std::string& set : point.sets) {
      const std::string key = set.substr(0, set.find('='));
      if (key.rfind(prefix, 0) != 0 || key == prefix + "dt") continue;
      throw UsageError("--vary " + key + ": " + base.reference +
                       " is the scene's reference, and each point would be measured against a "
                       "reference run with its own " +
                       key.substr(prefix.size()) +
                       " (an error of 0); vary dt only, or name another reference "
                       "(--set reference=NAME)");
    }
  }
}

// the grid, the shared job settings and the folder; every point checked before anything runs
SweepPlan plan_sweep(const SweepCommand& command) {
  SweepPlan plan;
  plan.base = load_scene_file(command.scene_file, command.overrides);
  validate_backend_knobs(plan.base);
  const std::vector<std::string> names = select_backends(plan.base, command.backends);
  plan.axes = parse_vary(command.vary);
  plan.points = sweep_grid(plan.axes, names);
  const std::vector<double> dts = check_points(command, plan.points);
  refuse_varied_reference(plan.base, plan.points);
  plan.out = command.out_dir.empty() ? "results/" + plan.base.name + "/sweep" : command.out_dir;
  plan.jobs.executable = command.executable.empty() ? "chainmail" : command.executable;
  plan.jobs.scene_file = command.scene_file;
  plan.jobs.cache = resolve_cache_dir(command.cache_dir);
  plan.jobs.overrides = command.overrides;
  plan.jobs.threads = sweep_threads(command);
  plan.jobs.reference_set =
      "reference_dt=" + csv_number(sweep_reference_dt(plan.base, plan.points, dts));
  return plan;
}

// at most one of --print-jobs, --reference-only, --gather, --slurm
void check_modes(const SweepCommand& command) {
  const int modes = command.print_jobs + command.reference_only + !command.gather.empty() +
                    !command.slurm.empty();
  if (modes > 1)
    throw UsageError("--print-jobs, --reference-only, --gather and --slurm: one at a time");
  if (!command.gather.empty() && !command.out_dir.empty())
    throw UsageError("--gather DIR writes sweep.csv into DIR itself: no --out with it");
}

}  // namespace

int sweep_command(const SweepCommand& command) {
  check_modes(command);
  const SweepPlan plan = plan_sweep(command);
  const SweepJobs& jobs = plan.jobs;
  const std::string& out = plan.out;
  const Scene& base = plan.base;
  const std::vector<SweepPoint>& points = plan.points;
  if (command.print_jobs) {
    print_jobs(command, plan);
    return kExitOk;
  }
  if (command.reference_only) {
    if (jobs.cache.empty()) throw UsageError("--reference-only: needs a cache, not --cache none");
    cache_reference(command, jobs);
    return interrupted() ? kExitInterrupted : kExitOk;
  }
  if (!command.gather.empty()) return gather_sweep(command, plan);
  if (!command.slurm.empty()) {
    write_slurm_script(command, plan);
    return kExitOk;
  }

  OutputFolder folder = OutputFolder::claim(out, "sweep", command.force);
  const std::string staging = folder.staging();
  cache_reference(command, jobs);
  run_points(command, jobs, points, staging);
  const int unstable = write_sweep_csv(plan.axes, points, staging);
  if (!interrupted())
    make_plot("plot_sweep.py", {staging + "/sweep.csv", staging + "/sweep.png", base.name});
  folder.commit();
  std::fprintf(stderr, "wrote %s/sweep.csv (%zu points, %d unstable)%s\n", out.c_str(),
               points.size(), unstable, interrupted() ? " (interrupted)" : "");
  return interrupted() ? kExitInterrupted : kExitOk;
}

}  // namespace chainmail

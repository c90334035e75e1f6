#include "bench/harness/suites/stability.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <sstream>

#include <nlohmann/json.hpp>

#include "backends/backend.hpp"
#include "bench/harness/commands/commands.hpp"
#include "bench/harness/common/data_dir.hpp"
#include "bench/harness/common/interrupt.hpp"
#include "bench/harness/output/number_format.hpp"
#include "bench/harness/output/output.hpp"
#include "bench/harness/output/output_folder.hpp"
#include "bench/harness/output/table_cells.hpp"
#include "bench/harness/run/run.hpp"
#include "core/parallel.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
using json = nlohmann::json;

const std::vector<StabilityCase>& stability_cases() {
  // quick mode: 4 x 4 sheets (the heavy ring stays at the middle of the bottom row), and the
  // spring study on 12 x 12 masses for 0.2 s
  const std::vector<std::string> sheet = {"weave.rows=4", "weave.cols=4"};
  const std::vector<std::string> cloth = {"duration=0.2", "weave.rows=12", "weave.cols=12"};
  static const std::vector<StabilityCase> cases = {
      {"heavy_weight.json", {}, 3, {"weave.rows=4", "weave.cols=4", "loads.0.ring=[3,2]"}},
      {"impact.json", {}, 3, sheet},
      {"large_dt.json", {}, 3, sheet},
      {"tight_rings.json", {}, 3, sheet},
      {"loose_rings.json", {}, 3, sheet},
      {"high_gravity.json", {}, 3, sheet},
      {"corners_pushed.json", {}, 3, sheet},
      // the stiffness study on the mass-spring document's own cloth
      {"springs_ks_500.json", {"massspring"}, 6, cloth},
      {"springs_ks_5000.json", {"massspring"}, 6, cloth},
      {"springs_ks_50000.json", {"massspring"}, 6, cloth},
      {"springs_ks_500000.json", {"massspring"}, 6, cloth},
  };
  return cases;
}

Scene load_stability_case(const StabilityCase& c, bool quick) {
  return load_scene_file(data_dir().scenes() + "/stability/" + c.file,
                         quick ? c.quick : std::vector<std::string>{});
}

namespace {

struct DtSearch {
  double largest = 0.0;
  std::string bound =
      "=";  // "=" found, ">=" stable at the top of the range, "<" unstable at the bottom
};

// largest stable dt by bisection in log space around the case's own dt
DtSearch largest_stable_dt(const Scene& scene, const Weave& weave, const std::string& backend,
                           double dt0, bool stable0, int steps, const RunOptions& options) {
  auto stable_at = [&](double dt) {
    json doc = scene_to_json(scene);
    doc["backends"][backend]["dt"] = dt;
    const Scene s = scene_from_json(doc, scene.file);
    const BackendRun run = run_backend(s, weave, backend, options);
    // too slow to finish is not unstable (nor is a run a signal stopped)
    return run.stable || run.verdict == Verdict::watchdog || run.verdict == Verdict::interrupted;
  };
  const BackendInfo* info = find_backend(backend);
  double dt_max = 1.0;
  for (const auto& k : info->knobs) {
    if (k.name == "dt") dt_max = k.max;
  }
  double lo, hi;
  if (stable0) {
    lo = dt0, hi = std::min(dt_max, 64.0 * dt0);
    if (stable_at(hi)) return {hi, ">="};
  } else {
    hi = dt0, lo = dt0 / 16.0;
    if (!stable_at(lo)) return {lo, "<"};
  }
  for (int it = 0; it < steps; ++it) {
    const double mid = std::sqrt(lo * hi);
    (stable_at(mid) ? lo : hi) = mid;
  }
  return {lo, "="};
}

// how the suite runs a backend: for the verdict, and for each step of the dt search
struct SuiteRuns {
  RunOptions verdict, search;
};

SuiteRuns suite_runs(const StabilityCommand& command) {
  SuiteRuns runs;
  runs.verdict.progress = false;
  runs.verdict.other_pair_metrics = true;
  runs.verdict.max_wall_seconds = command.max_wall_seconds;
  runs.verdict.threads = command.threads > 0 ? command.threads : hardware_threads();
  runs.search = runs.verdict;
  runs.search.other_pair_metrics = false;
  return runs;
}

// stability.csv and stability.md as they fill
struct StabilityTables {
  std::ostringstream csv, md;
  int unstable = 0;  // runs not stable at default settings
};

void start_tables(StabilityTables& t) {
  t.csv << "case,backend,dt,verdict,settled,overstretched,largest_stable_dt,bound,max_stretch,"
           "broken_links,penetrating_linked,penetration_max_linked,false_links,max_speed,"
           "ms_per_step\n";
  t.md << "# Stability suite\n\nEach case runs every backend at its default knobs (the verdict), "
          "then bisects for the largest stable dt (log-space, 3 steps, 6 for the spring study; "
          "`>=` = stable at the top of the searched range, `<` = unstable at the bottom). Depth: "
          "the deepest interpenetration of linked rings, in wire radii a.\n\n"
          "| case | backend | dt (s) | verdict | settled | overstretched | largest stable dt (s) | "
          "max_stretch | broken_links | penetrating_linked | depth max (a) | max_speed (m/s) |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
}

// one backend's run of a case: a row of each table
void add_rows(StabilityTables& t, const Scene& scene, const std::string& backend,
              const BackendRun& run, const DtSearch& dt) {
  const Metrics& m = run.final_metrics();
  t.unstable += !run.stable;
  t.csv << scene.name << ',' << backend << ',' << csv_number(run.dt) << ','
        << to_string(run.verdict) << ',' << yes_no_cell(run.settled) << ','
        << yes_no_cell(run.overstretched) << ',' << csv_number(dt.largest) << ',' << dt.bound << ','
        << csv_number(m.max_stretch) << ',' << m.broken_links << ',' << m.penetrating_linked << ','
        << csv_number(m.penetration_max_linked) << ',' << m.false_links << ','
        << csv_number(m.max_speed) << ',' << csv_number(run.ms_per_step()) << '\n';
  t.md << "| " << scene.name << " | " << backend << " | " << run.dt << " | "
       << to_string(run.verdict) << " | " << yes_no_cell(run.settled) << " | "
       << yes_no_cell(run.overstretched) << " | " << (dt.bound == "=" ? "" : dt.bound + " ")
       << table_number(dt.largest, 3) << " | " << table_number(m.max_stretch, 4) << " | "
       << m.broken_links << " | " << m.penetrating_linked << " | "
       << wire_radii_cell(m.penetration_max_linked, scene.ring.wire_radius) << " | "
       << table_number(m.max_speed, 3) << " |\n";
}

// the backends a case runs: its own list (those of it that were asked for), else those asked for
std::vector<std::string> case_backends(const StabilityCase& c, const Scene& scene,
                                       const std::vector<std::string>& requested) {
  if (c.only.empty())
    return select_backends(scene,
                           requested.empty() ? std::vector<std::string>{kAllBackends} : requested);
  std::vector<std::string> names;
  for (const auto& name : c.only) {
    if (requested.empty() || std::find(requested.begin(), requested.end(), name) != requested.end())
      names.push_back(name);
  }
  return names;
}

// a case through each of its backends: the verdict at the case's knobs, then the dt search
void run_case(const StabilityCase& c, const Scene& scene, const StabilityCommand& command,
              const SuiteRuns& runs, StabilityTables& tables) {
  const Weave weave = make_weave(scene.weave, scene.ring);
  for (const auto& name : case_backends(c, scene, command.backends)) {
    if (interrupted()) return;
    if (command.progress)
      std::fprintf(stderr, "stability: %-16s %s\n", scene.name.c_str(), name.c_str());
    BackendRun run;
    try {
      run = run_backend(scene, weave, name, runs.verdict);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "  %s: %s\n", name.c_str(), e.what());
      continue;
    }
    if (interrupted()) return;
    const DtSearch dt =
        largest_stable_dt(scene, weave, name, run.dt, run.stable, c.bisection_steps, runs.search);
    if (interrupted()) return;
    add_rows(tables, scene, name, run, dt);
  }
}

void finish_tables(StabilityTables& t, const std::vector<Scene>& scenes) {
  t.md << "\nCases:\n\n";
  for (const Scene& s : scenes) t.md << "- `" << s.name << "`: " << s.description << "\n";
  if (interrupted()) t.md << "\nInterrupted: the cases above are those that finished.\n";
}

}  // namespace

int stability_command(const StabilityCommand& command) {
  // every case loaded and the names checked: bad input before anything runs or is written
  const std::vector<StabilityCase>& cases = stability_cases();
  std::vector<Scene> scenes;
  for (const StabilityCase& c : cases) scenes.push_back(load_stability_case(c, command.quick));
  if (!command.backends.empty()) select_backends(scenes[0], command.backends);
  OutputFolder folder = OutputFolder::claim(command.out_dir, "stability", command.force);

  const SuiteRuns runs = suite_runs(command);
  StabilityTables tables;
  start_tables(tables);
  for (size_t i = 0; i < cases.size(); ++i) run_case(cases[i], scenes[i], command, runs, tables);
  finish_tables(tables, scenes);
  write_file_atomic(folder.staging() + "/stability.csv", tables.csv.str());
  write_file_atomic(folder.staging() + "/stability.md", tables.md.str());
  folder.commit();
  std::fprintf(stderr, "wrote %s/stability.{csv,md} (%d unstable at default settings)%s\n",
               command.out_dir.c_str(), tables.unstable, interrupted() ? " (interrupted)" : "");
  // instabilities are the suite's findings, not a failure of the suite
  return interrupted() ? kExitInterrupted : kExitOk;
}

}  // namespace chainmail

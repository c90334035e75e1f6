#include "bench/harness/suites.hpp"

#include <fcntl.h>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench/harness/commands.hpp"
#include "bench/harness/interrupt.hpp"
#include "bench/harness/output.hpp"
#include "bench/harness/output_folder.hpp"
#include "bench/harness/render_output.hpp"

extern char** environ;

namespace chainmail {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

std::string shell_quote(const std::string& s) {
  // plain words stay as they are, so that printed command lines read naturally
  if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                        "0123456789-_./,:+") == std::string::npos) {
    return s;
  }
  std::string out = "'";
  for (char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  std::string part;
  while (std::getline(stream, part, sep)) parts.push_back(part);
  return parts;
}

// runs `count` jobs on `jobs` threads; job(k) is called once for each k
void run_parallel(int count, int jobs, const std::function<void(int)>& job) {
  std::atomic<int> next{0};
  std::vector<std::thread> workers;
  for (int w = 0; w < std::max(1, jobs); ++w) {
    workers.emplace_back([&] {
      for (int k = next++; k < count; k = next++) job(k);
    });
  }
  for (auto& t : workers) t.join();
}

// runs `argv` to completion with stdout and stderr into `log`; a signal to this process is passed
// on as SIGTERM (so the child writes what it finished). Returns the exit status (-1: no start).
int run_child(const std::vector<std::string>& argv, const std::string& log) {
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&files, 1, 2);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int failed = posix_spawn(&pid, args[0], &files, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  if (failed) return -1;
  bool passed_on = false;
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (interrupted() && !passed_on) ::kill(pid, SIGTERM), passed_on = true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string source_dir() {
  if (const char* env = std::getenv("CHAINMAIL_SOURCE_DIR")) return env;
  return CHAINMAIL_SOURCE_DIR;
}

bool make_plot(const std::string& script, const std::vector<std::string>& args) {
  const std::string python = plotting_python();
  if (python.empty()) {
    std::fprintf(stderr, "chainmail: no python3 with matplotlib: plot skipped\n");
    return false;
  }
  std::string command = python + " " + shell_quote(source_dir() + "/bench/" + script);
  for (const auto& a : args) command += " " + shell_quote(a);
  return std::system(command.c_str()) == 0;
}

}  // namespace

std::string plotting_python() {
  for (const char* candidate : {"/usr/bin/python3", "python3"}) {
    const std::string probe = std::string(candidate) + " -c 'import matplotlib' >/dev/null 2>&1";
    if (std::system(probe.c_str()) == 0) return candidate;
  }
  return "";
}

std::optional<double> catenary_error(const Scene& scene, const Weave& weave,
                                     const RingFrame& frame) {
  if (weave.type != WeaveType::chain) return std::nullopt;
  const std::vector<int> pins = resolve_pins(scene, weave);
  const int n = weave.size();
  if (pins.size() != 2 || pins[0] != 0 || pins[1] != n - 1) return std::nullopt;
  const Vec3 down = scene.gravity.normalized();
  const Vec3 p0 = weave.rest_position.col(0), p1 = weave.rest_position.col(n - 1);
  if (std::abs((p1 - p0).dot(down)) > 1e-9) return std::nullopt;  // pins at equal height only
  const double span = (p1 - p0).norm();
  const double length = (n - 1) * scene.ring.max_link_distance();
  if (length <= span) return std::nullopt;
  // catenary parameter A from length = 2 A sinh(span / 2A), by bisection on A
  double lo = 1e-9 * span, hi = 1e6 * span;
  for (int it = 0; it < 200; ++it) {
    const double mid = std::sqrt(lo * hi);
    (2.0 * mid * std::sinh(span / (2.0 * mid)) > length ? lo : hi) = mid;
  }
  const double a = std::sqrt(lo * hi);
  const double expected = a * (std::cosh(span / (2.0 * a)) - 1.0);
  double sag = 0.0;
  for (int i = 0; i < n; ++i) sag = std::max(sag, (frame.position.col(i) - p0).dot(down));
  return std::abs(sag - expected) / expected;
}

// ---------------------------------------------------------------------------------------------
// sweep

int sweep_command(const SweepCommand& command) {
  const Scene base = load_scene_file(command.scene_file, command.overrides);
  validate_backend_knobs(base);
  const std::vector<std::string> names = select_backends(base, command.backends);

  // the grid of knob values
  std::vector<std::pair<std::string, std::vector<std::string>>> axes;
  for (const auto& v : command.vary) {
    const auto eq = v.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == v.size()) {
      throw SceneError("--vary '" + v + "': expected KEY=v1,v2,...");
    }
    axes.push_back({v.substr(0, eq), split(v.substr(eq + 1), ',')});
  }
  if (axes.empty()) throw SceneError("--vary: at least one KEY=v1,v2,... is needed");

  struct Point {
    std::string backend;
    std::vector<std::string> values;  // one per axis
    std::vector<std::string> sets;    // effective --set overrides
    double dt = 0.0;                  // s, the point's own backend's time step
  };
  std::vector<Point> points;
  std::vector<size_t> index(axes.size(), 0);
  for (const auto& backend : names) {
    std::fill(index.begin(), index.end(), 0);
    std::vector<std::vector<std::string>> seen;
    while (true) {
      Point p{backend, {}, command.overrides};
      std::vector<std::string> effective;
      for (size_t a = 0; a < axes.size(); ++a) {
        std::string key = axes[a].first;
        const auto placeholder = key.find("{backend}");
        if (placeholder != std::string::npos) key.replace(placeholder, 9, backend);
        const std::string& value = axes[a].second[index[a]];
        p.values.push_back(value);
        // another backend's knob does not change this backend's run
        if (key.rfind("backends.", 0) == 0 && key.rfind("backends." + backend + ".", 0) != 0) {
          p.values.back() = "";
          continue;
        }
        effective.push_back(key + "=" + value);
      }
      if (std::find(seen.begin(), seen.end(), effective) == seen.end()) {
        seen.push_back(effective);
        p.sets.insert(p.sets.end(), effective.begin(), effective.end());
        // validate now: a bad value is bad input before anything runs
        const Scene scene = load_scene_file(command.scene_file, p.sets);
        validate_backend_knobs(scene);
        check_budget(scene, estimate_run(scene, {backend}, 0.0), Budget{});
        p.dt = resolve_knobs(scene, *find_backend(backend)).at("dt");
        points.push_back(p);
      }
      size_t a = 0;
      while (a < axes.size() && ++index[a] == axes[a].second.size()) index[a++] = 0;
      if (a == axes.size()) break;
    }
  }

  const std::string out =
      command.out_dir.empty() ? "results/" + base.name + "/sweep" : command.out_dir;
  const std::string exe = command.executable.empty() ? "chainmail" : command.executable;
  const std::string cache = resolve_cache_dir(command.cache_dir);
  // one point's command line, writing into `folder` (argv form, no shell in between)
  auto job_args = [&](size_t k, const std::string& folder) {
    std::vector<std::string> args = {exe,
                                     "run",
                                     command.scene_file,
                                     "--backends",
                                     points[k].backend,
                                     "--out",
                                     folder + "/points/" + std::to_string(k),
                                     "--cache",
                                     cache.empty() ? "none" : cache,
                                     "--quiet"};
    for (const auto& s : points[k].sets) args.insert(args.end(), {"--set", s});
    return args;
  };
  // every point is measured against one reference run, whatever the point's knobs (printed jobs
  // too): the scene's reference_dt when it names one, else the reference backend at the finest dt
  // that this sweep runs it at (or its dt in the scene, when the sweep does not run it)
  double reference_dt = base.reference_dt;
  if (reference_dt <= 0.0) {
    reference_dt = resolve_knobs(base, *find_backend(base.reference)).at("dt");
    for (const Point& p : points) {
      if (p.backend == base.reference) reference_dt = std::min(reference_dt, p.dt);
    }
  }
  const std::string reference_set = "reference_dt=" + csv_number(reference_dt);
  for (auto& p : points) p.sets.push_back(reference_set);
  if (command.print_jobs) {
    for (size_t k = 0; k < points.size(); ++k) {
      std::string line;
      for (const auto& a : job_args(k, out)) line += (line.empty() ? "" : " ") + shell_quote(a);
      std::printf("%s\n", line.c_str());
    }
    return kExitOk;
  }
  OutputFolder folder = OutputFolder::claim(out, "sweep", command.force);
  const std::string staging = folder.staging();

  // the reference run once, before the points share it through the cache
  RunOptions reference_options;
  reference_options.progress = command.progress;
  reference_options.cache_dir = cache;
  std::vector<std::string> reference_sets = command.overrides;
  reference_sets.push_back(reference_set);
  const Scene reference_scene = load_scene_file(command.scene_file, reference_sets);
  if (!cache.empty() && !interrupted())
    ensure_reference_cached(reference_scene, reference_scene.reference, reference_options);

  fs::create_directories(staging + "/points");
  std::mutex print;
  std::atomic<int> done{0};
  run_parallel(static_cast<int>(points.size()), command.jobs, [&](int k) {
    if (interrupted()) return;
    run_child(job_args(k, staging), staging + "/points/" + std::to_string(k) + ".log");
    std::lock_guard<std::mutex> lock(print);
    if (command.progress) std::fprintf(stderr, "  sweep point %d / %zu\n", ++done, points.size());
  });

  // one row per point, read back from each point's summary.json
  std::ostringstream csv;
  csv << "backend";
  for (const auto& axis : axes) csv << ',' << axis.first;
  csv << ",wall_per_sim_s,ms_per_step,error_m,catenary_error,stable,verdict\n";
  int unstable = 0;
  for (size_t k = 0; k < points.size(); ++k) {
    const Point& p = points[k];
    csv << p.backend;
    for (const auto& v : p.values) csv << ',' << v;
    std::ifstream in(staging + "/points/" + std::to_string(k) + "/summary.json");
    json summary = json::parse(in, nullptr, false);
    if (summary.is_discarded() || !summary["backends"].contains(p.backend)) {
      csv << ",,,,,false," << (interrupted() ? "interrupted" : "error") << "\n";
      ++unstable;
      continue;
    }
    const json& b = summary["backends"][p.backend];
    auto number = [](const json& v) { return v.is_number() ? v.get<double>() : NAN; };
    // cost per simulated second of what was simulated: an unstable run stops early
    const double simulated = number(b["steps"]) * number(b["dt"]);
    const double duration = simulated > 0.0 ? simulated : number(summary["scene"]["duration"]);
    const double error = b["final"].contains("drape_rms") ? number(b["final"]["drape_rms"]) : NAN;
    const double cat = b.contains("catenary_error") ? number(b["catenary_error"]) : NAN;
    csv << ',' << csv_number(number(b["wall_s"]) / duration) << ','
        << csv_number(number(b["ms_per_step"])) << ',' << csv_number(error) << ','
        << csv_number(cat) << ',' << (b["stable"].get<bool>() ? "true" : "false") << ','
        << b["verdict"].get<std::string>() << '\n';
    unstable += !b["stable"].get<bool>();
  }
  write_file_atomic(staging + "/sweep.csv", csv.str());
  if (!interrupted())
    make_plot("plot_sweep.py", {staging + "/sweep.csv", staging + "/sweep.png", base.name});
  folder.commit();
  std::fprintf(stderr, "wrote %s/sweep.csv (%zu points, %d unstable)%s\n", out.c_str(),
               points.size(), unstable, interrupted() ? " (interrupted)" : "");
  return interrupted() ? kExitInterrupted : kExitOk;
}

}  // namespace chainmail

// ---------------------------------------------------------------------------------------------
// stability suite

namespace chainmail {
namespace {

struct StabilityCase {
  std::string name;
  std::string description;
  json scene;
  std::vector<std::string> only;  // restrict to these backends (empty: every backend)
  int bisection_steps = 3;        // halvings (in log space) of the searched dt range
};

json sheet_scene(const std::string& name, int size, bool hanging) {
  json scene = {{"name", name},
                {"weave",
                 {{"type", "4in1"},
                  {"rows", size},
                  {"cols", size},
                  {"plane", hanging ? "xy" : "xz"},
                  {"center", {0, 0.1, 0}}}},
                {"duration", 0.3},
                {"sample_interval", 0.05},
                {"features", {{"self_contact", true}}}};
  if (hanging) scene["pins"] = json::array({{{"edge", "top"}}});
  return scene;
}

std::vector<StabilityCase> stability_cases(bool quick) {
  const int size = quick ? 4 : 6;
  std::vector<StabilityCase> cases;
  {
    json s = sheet_scene("heavy_weight", size, true);
    s["loads"] = json::array({{{"ring", {size - 1, size / 2}}, {"mass_factor", 100.0}}});
    cases.push_back(
        {"heavy_weight", "a ring 100x heavier hanging from the bottom of a curtain", s, {}});
  }
  {
    json s = sheet_scene("impact", size, false);
    s["initial_velocity"] = {0, -10, 0};
    s["weave"]["center"] = {0, 0.05, 0};
    s["colliders"] = json::array({{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 0.02}},
                                  {{"type", "plane"}, {"point", {0, -0.02, 0}}}});
    s["duration"] = 0.2;
    s["stability"] = {{"max_speed", 40.0}};
    cases.push_back({"impact", "a sheet hitting a sphere at 10 m/s", s, {}});
  }
  {
    json s = sheet_scene("large_dt", size, true);
    for (const auto& info : backend_registry()) {
      for (const auto& knob : info.knobs) {
        if (knob.name == "dt")
          s["backends"][info.name] = {{"dt", std::min(knob.max, 10.0 * knob.default_value)}};
      }
    }
    cases.push_back({"large_dt", "a curtain at ten times each backend's default dt", s, {}});
  }
  {
    json s = sheet_scene("tight_rings", size, true);
    s["ring"] = {{"wire_diameter", 0.0016}, {"inner_diameter", 0.0056}};
    cases.push_back({"tight_rings", "a curtain of tight rings, aspect ratio 3.5", s, {}});
  }
  {
    json s = sheet_scene("loose_rings", size, true);
    s["ring"] = {{"wire_diameter", 0.0016}, {"inner_diameter", 0.0128}};
    cases.push_back({"loose_rings", "a curtain of loose rings, aspect ratio 8", s, {}});
  }
  {
    json s = sheet_scene("high_gravity", size, true);
    s["gravity"] = {0, -98.1, 0};
    cases.push_back({"high_gravity", "a curtain under ten times gravity", s, {}});
  }
  {
    json s = sheet_scene("corners_pushed", size, false);
    s["pins"] = json::array({{{"corner", "top_left"}},
                             {{"corner", "top_right"}},
                             {{"corner", "bottom_left"}},
                             {{"corner", "bottom_right"}}});
    // the sphere's top 1 mm under the sheet's rings (wire radius 0.8 mm): the sheet starts clear
    // of it and gravity presses its middle onto it, so the fabric must carry its own weight from
    // below while its corners hold it in both directions (a start in deep overlap would test the
    // rigid solvers' depenetration instead)
    s["colliders"] = json::array(
        {{{"type", "sphere"}, {"center", {0, 0.1 - 0.001 - 0.03, 0}}, {"radius", 0.03}}});
    s["stability"] = {{"links_must_hold", true}};
    cases.push_back(
        {"corners_pushed",
         "a sheet pinned at its corners and supported from below by a sphere (the paper's "
         "failure case)",
         s,
         {}});
  }
  // the stiffness study on the document's own cloth (two pinned corners, 50 x 50 masses over
  // 1 m, dt 1/2700 s): structural and shear springs at ks, bending at ks / 5 as in the scene
  const json cloth = load_scene_file(source_dir() + "/bench/scenes/cloth/pinned2.json").resolved;
  for (double ks : {500.0, 5000.0, 50000.0, 500000.0}) {
    json s = cloth;
    char name[64];
    std::snprintf(name, sizeof name, "springs_ks_%g", ks);
    s["name"] = name;
    s["duration"] = quick ? 0.2 : 1.0;
    s["sample_interval"] = 0.05;
    if (quick) s["weave"]["rows"] = 12, s["weave"]["cols"] = 12;
    auto& knobs = s["backends"]["massspring"];
    knobs["ks"] = ks, knobs["shear_ks"] = ks, knobs["bend_ks"] = ks / 5.0;
    cases.push_back({name,
                     "the document's two-corner cloth with spring constant ks (N/m) (bending ks/5)",
                     s,
                     {"massspring"},
                     6});
  }
  return cases;
}

struct DtSearch {
  double largest = 0.0;
  std::string bound =
      "=";  // "=" found, ">=" stable at the top of the range, "<" unstable at the bottom
};

// largest stable dt by bisection in log space around the case's own dt
DtSearch largest_stable_dt(const Scene& scene, const Weave& weave, const std::string& backend,
                           double dt0, bool stable0, int steps, const RunOptions& options) {
  auto stable_at = [&](double dt) {
    json doc = scene.resolved;
    doc["backends"][backend]["dt"] = dt;
    const Scene s = scene_from_json(doc, scene.file);
    const BackendRun run = run_backend(s, weave, backend, options);
    // too slow to finish is not unstable (nor is a run a signal stopped)
    return run.stable || run.verdict == "watchdog" || run.verdict == "interrupted";
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

}  // namespace

int stability_command(const StabilityCommand& command) {
  RunOptions options;
  options.progress = false;
  options.other_pair_metrics = true;
  options.max_wall_seconds = command.max_wall_seconds;
  RunOptions search = options;
  search.other_pair_metrics = false;
  // bad names are bad input before anything runs or is written
  const std::vector<StabilityCase> cases = stability_cases(command.quick);
  if (!command.backends.empty())
    select_backends(scene_from_json(cases[0].scene, "stability"), command.backends);
  OutputFolder folder = OutputFolder::claim(command.out_dir, "stability", command.force);

  std::ostringstream csv, md;
  csv << "case,backend,dt,verdict,settled,overstretched,largest_stable_dt,bound,max_stretch,"
         "broken_links,penetrating_linked,penetration_max_linked,false_links,max_speed,"
         "ms_per_step\n";
  md << "# Stability suite\n\nEach case runs every backend at its default knobs (the verdict), "
        "then bisects for the largest stable dt (log-space, 3 steps, 6 for the spring study; "
        "`>=` = stable at the top of the searched range, `<` = unstable at the bottom). Depth: "
        "the deepest interpenetration of linked rings, in wire radii a.\n\n"
        "| case | backend | dt (s) | verdict | settled | overstretched | largest stable dt (s) | "
        "max_stretch | broken_links | penetrating_linked | depth max (a) | max_speed (m/s) |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  int unstable = 0;
  auto yes_no = [](const std::optional<bool>& v) { return v ? (*v ? "yes" : "no") : "-"; };
  for (const StabilityCase& c : cases) {
    const Scene scene = scene_from_json(c.scene, "stability/" + c.name);
    const Weave weave = make_weave(scene.weave, scene.ring);
    std::vector<std::string> names =
        c.only.empty()
            ? select_backends(scene, command.backends.empty() ? std::vector<std::string>{"all"}
                                                              : command.backends)
            : c.only;
    for (const auto& name : names) {
      if (interrupted()) break;
      if (!c.only.empty() && !command.backends.empty() &&
          std::find(command.backends.begin(), command.backends.end(), name) ==
              command.backends.end()) {
        continue;
      }
      if (command.progress)
        std::fprintf(stderr, "stability: %-16s %s\n", c.name.c_str(), name.c_str());
      BackendRun run;
      try {
        run = run_backend(scene, weave, name, options);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "  %s: %s\n", name.c_str(), e.what());
        continue;
      }
      if (interrupted()) break;
      const DtSearch dt =
          largest_stable_dt(scene, weave, name, run.dt, run.stable, c.bisection_steps, search);
      if (interrupted()) break;
      const Metrics& m = run.final_metrics();
      unstable += !run.stable;
      csv << c.name << ',' << name << ',' << csv_number(run.dt) << ',' << run.verdict << ','
          << yes_no(run.settled) << ',' << yes_no(run.overstretched) << ','
          << csv_number(dt.largest) << ',' << dt.bound << ',' << csv_number(m.max_stretch) << ','
          << m.broken_links << ',' << m.penetrating_linked << ','
          << csv_number(m.penetration_max_linked) << ',' << m.false_links << ','
          << csv_number(m.max_speed) << ',' << csv_number(run.ms_per_step()) << '\n';
      md << "| " << c.name << " | " << name << " | " << run.dt << " | " << run.verdict << " | "
         << yes_no(run.settled) << " | " << yes_no(run.overstretched) << " | "
         << (dt.bound == "=" ? "" : dt.bound + " ") << table_number(dt.largest, 3) << " | "
         << table_number(m.max_stretch, 4) << " | " << m.broken_links << " | "
         << m.penetrating_linked << " | "
         << table_number(m.penetration_max_linked / scene.ring.wire_radius, 3) << " | "
         << table_number(m.max_speed, 3) << " |\n";
    }
  }
  md << "\nCases:\n\n";
  for (const StabilityCase& c : cases) md << "- `" << c.name << "`: " << c.description << "\n";
  if (interrupted()) md << "\nInterrupted: the cases above are those that finished.\n";
  write_file_atomic(folder.staging() + "/stability.csv", csv.str());
  write_file_atomic(folder.staging() + "/stability.md", md.str());
  folder.commit();
  std::fprintf(stderr, "wrote %s/stability.{csv,md} (%d unstable at default settings)%s\n",
               command.out_dir.c_str(), unstable, interrupted() ? " (interrupted)" : "");
  // instabilities are the suite's findings, not a failure of the suite
  return interrupted() ? kExitInterrupted : kExitOk;
}

}  // namespace chainmail

// ---------------------------------------------------------------------------------------------
// the main bench

namespace chainmail {

namespace {

// one scene's rows of the bench's timing and metric tables
void bench_rows(const SceneRun& run, std::ostringstream& timing, std::ostringstream& timing_csv,
                std::ostringstream& metrics) {
  const Scene& scene = run.scene;
  const double a = scene.ring.wire_radius;
  double plausible_cost = 0.0;
  for (const auto& r : run.runs) {
    if (r.name == "plausible" && r.dt > 0) plausible_cost = r.ms_per_step() / r.dt;
  }
  auto yes_no = [](const std::optional<bool>& v) { return v ? (*v ? "yes" : "no") : "-"; };
  for (const auto& r : run.runs) {
    const double relative = plausible_cost > 0 ? (r.ms_per_step() / r.dt) / plausible_cost : NAN;
    timing << "| " << scene.name << " | " << run.weave.size() << " | " << r.name << " | " << r.dt
           << " | " << table_number(r.ms_per_step(), 4) << " | "
           << table_number(r.realtime_factor(), 3) << " | "
           << (std::isnan(relative) ? "-" : table_number(relative, 3) + "x") << " | " << r.verdict
           << " |\n";
    timing_csv << scene.name << ',' << run.weave.size() << ',' << r.name << ',' << csv_number(r.dt)
               << ',' << r.steps << ',' << csv_number(r.ms_per_step()) << ','
               << csv_number(r.realtime_factor()) << ',' << r.verdict << ',' << std::hex << r.hash
               << std::dec << '\n';
    metrics << "| " << scene.name << " | " << r.name << " | " << r.verdict << " | "
            << yes_no(r.settled) << " | " << yes_no(r.overstretched) << " | ";
    if (!r.started()) {
      metrics << "- | - | - | - | - | - | - | - | - | - | - |\n";
      continue;
    }
    const Metrics& m = r.final_metrics();
    metrics << table_number(m.max_stretch, 4) << " | " << table_number(m.mean_stretch, 4) << " | "
            << m.penetrating_linked << " | " << table_number(m.penetration_max_linked / a, 3)
            << " / " << table_number(m.penetration_mean_linked / a, 3) << " | "
            << m.penetrating_other << " | " << table_number(m.penetration_max_other / a, 3) << " / "
            << table_number(m.penetration_mean_other / a, 3) << " | " << m.broken_links << " | "
            << m.false_links << " | " << (m.drape_rms ? table_number(1e3 * *m.drape_rms, 3) : "-")
            << " | " << (m.drape_coefficient ? table_number(*m.drape_coefficient, 3) : "-") << " | "
            << (r.catenary_error ? table_number(100.0 * *r.catenary_error, 3) + " %" : "-")
            << " |\n";
  }
}

}  // namespace

int bench_command(const BenchCommand& command) {
  struct BenchScene {
    std::string file;
    std::vector<std::string> full, quick;  // --set overrides for the bench sizes
  };
  const std::string scenes = source_dir() + "/bench/scenes/";
  // sizes for a bench of a few minutes on 2 cores (the rigid backends cost the most): 16 x 16
  // sheets (the paper's 30 x 30 is measured by `chainmail run` on the scene files themselves)
  const std::vector<BenchScene> set = {
      {"curtain.json",
       {"weave.rows=16", "weave.cols=16", "duration=1.0"},
       {"weave.rows=4", "weave.cols=4", "duration=0.05"}},
      {"table_cloth.json",
       {"weave.rows=16", "weave.cols=16", "duration=1.0", "colliders.0.radius=0.03",
        "support.radius=0.03"},
       {"weave.rows=4", "weave.cols=4", "duration=0.05"}},
      {"sphere_drape.json",
       {"weave.rows=16", "weave.cols=16", "duration=1.0", "colliders.0.radius=0.03",
        "colliders.0.center=[0,0.12,0]"},
       {"weave.rows=4", "weave.cols=4", "duration=0.05"}},
      {"chain_catenary.json", {}, {"weave.cols=8", "duration=0.05"}},
      {"chain_pile.json", {"weave.cols=40", "duration=1.0"}, {"weave.cols=6", "duration=0.05"}},
  };
  const auto started = std::chrono::steady_clock::now();
  // bad names are bad input before anything runs or is written
  if (!command.backends.empty())
    select_backends(load_scene_file(scenes + set[0].file), command.backends);
  OutputFolder folder = OutputFolder::claim(command.out_dir, "bench", command.force);
  const std::string out = folder.staging();
  // reference runs are cached by scene, knobs and build; a bench still starts with a cache of its
  // own (inside its staging folder, gone when it is done) so it measures every reference afresh
  const std::string cache = out + "/.cache";
  std::function<void(const SceneRun&, const std::string&)> render;
  if (command.render) {
    try {
      render = make_render_writer("", "", /*last_only=*/true);  // the final frame keeps it small
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench: no frames rendered (%s)\n", e.what());
    }
  }

  // every scene through every backend
  std::ostringstream timing, metrics, timing_csv;
  timing << "# Timing\n\nms per step (wall time inside `step()` only), real-time factor "
            "(simulated / wall seconds) and cost per simulated second relative to `plausible`.\n\n"
            "| scene | rings | backend | dt (s) | ms/step | real-time factor | cost vs plausible | "
            "verdict |\n"
            "|---|---|---|---|---|---|---|---|\n";
  timing_csv << "scene,rings,backend,dt,steps,ms_per_step,realtime_factor,verdict,hash\n";
  metrics << "# Final metrics\n\n`drape_rms` against each scene's reference backend (mm); "
             "`catenary` is the chain's sag error against the analytic catenary; depths are the "
             "deepest and mean interpenetration of linked (and of other) pairs in wire radii a; "
             "settled: kinetic energy at the end below "
          << table_number(100.0 * kSettledEnergyFraction, 3)
          << " % of the energy released; overstretched: a link stretched above "
          << table_number(1.0 + kOverstretchTolerance, 4)
          << " (impossible for real rings).\n\n"
             "| scene | backend | verdict | settled | overstretched | max_stretch | mean_stretch | "
             "penetrating_linked | depth max/mean linked (a) | penetrating_other | "
             "depth max/mean other (a) | broken_links | false_links | drape_rms (mm) | "
             "drape_coefficient | catenary |\n"
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const BenchScene& b : set) {
    if (interrupted()) break;
    const Scene scene = load_scene_file(scenes + b.file, command.quick ? b.quick : b.full);
    RunOptions options;
    options.backends =
        command.backends.empty() ? std::vector<std::string>{"all"} : command.backends;
    options.progress = command.progress;
    options.cache_dir = cache;
    options.folder = out + "/" + scene.name;
    options.keep_stream = static_cast<bool>(render);
    const SceneRun run = run_scene(scene, options);
    OutputOptions output;
    output.render = render;
    write_run_folder(run, options.folder, output);
    bench_rows(run, timing, timing_csv, metrics);
  }
  write_file_atomic(out + "/timing.md", timing.str());
  write_file_atomic(out + "/timing.csv", timing_csv.str());
  write_file_atomic(out + "/metrics.md", metrics.str());

  // error against run time: the curtain and the table cloth over each backend's dt
  // (8 x 8 sheets, about 5 cm: the table shrinks to 1.5 cm so that the cloth drapes over it)
  const std::vector<std::pair<std::string, std::vector<std::string>>> sweeps = {
      {"curtain.json", {"weave.rows=8", "weave.cols=8", "duration=0.5"}},
      {"table_cloth.json",
       {"weave.rows=8", "weave.cols=8", "duration=0.5", "colliders.0.radius=0.015",
        "support.radius=0.015"}}};
  for (const auto& [file, overrides] : sweeps) {
    if (interrupted()) break;
    SweepCommand sweep;
    sweep.scene_file = scenes + file;
    sweep.overrides =
        command.quick ? std::vector<std::string>{"weave.rows=4", "weave.cols=4", "duration=0.05"}
                      : overrides;
    sweep.vary = {command.quick ? "backends.{backend}.dt=0.004,0.002"
                                : "backends.{backend}.dt=0.008,0.004,0.002,0.001,0.0005"};
    sweep.backends = command.backends.empty() ? std::vector<std::string>{"all"} : command.backends;
    sweep.out_dir = out + "/sweep/" + fs::path(file).stem().string();
    sweep.jobs = command.jobs;
    sweep.executable = command.executable;
    sweep.progress = command.progress;
    sweep.cache_dir = cache;
    sweep_command(sweep);
  }

  // stiff and extreme cases
  if (!interrupted()) {
    StabilityCommand stability;
    stability.backends = command.backends;
    stability.out_dir = out + "/stability";
    stability.quick = command.quick;
    stability.max_wall_seconds = command.quick ? 5.0 : 10.0;
    stability.progress = command.progress;
    stability_command(stability);
  }

  std::ostringstream readme;
  readme
      << "# Results of `chainmail bench`\n\n"
         "Regenerate with `./scripts/bench.sh` (or `chainmail bench --out results/bench`). Every "
         "scene "
         "runs through every backend from the same rest layout; numbers below come from one "
         "run on the machine that produced them (2 cores), so compare ratios, not absolutes.\n\n"
         "- `timing.md` / `timing.csv` — ms per step, real-time factor, cost relative to "
         "`plausible`, verdict and final-frame hash for each scene and backend.\n"
         "- `metrics.md` — final metrics: stretch (centre distance / inner diameter; above 1 is "
         "impossible for real rings), interpenetrating pairs among neighbours and others, broken "
         "and false links, drape error against the reference backend, Cusick drape coefficient "
         "(table_cloth), catenary sag error (chain_catenary).\n"
         "- `<scene>/` — each scene's `summary.json`, `metrics.csv` (every sample), `table.md` and "
         "`images/` (the final frame of every backend side by side, when rendering is available).\n"
         "- `sweep/<scene>/` — error against run time: the curtain and the table cloth (8 x 8) at "
         "a range of dt per backend; `sweep.csv` (wall seconds per simulated second, drape error "
         "against the reference run) and `sweep.png` (log-log, Pareto front marked).\n"
         "- `stability/` — the stiff and extreme cases: verdict at default settings and the "
         "largest stable dt found by bisection.\n"
         "- `stability/` is written last; the gallery (`../curtain_30x30/`), the shader "
         "pictures (`../shaders/`) and the renderer benchmark (`../micro_render.csv`) come from "
         "their own scripts, not from `bench`.\n";
  const double minutes =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() / 60.0;
  char took[96];
  std::snprintf(took, sizeof took, "\nThis bench took %.1f minutes.\n", minutes);
  readme << took;
  if (interrupted()) readme << "\nInterrupted: only what finished is here.\n";
  write_file_atomic(out + "/README.md", readme.str());
  std::error_code ignored;
  fs::remove_all(cache, ignored);
  folder.commit();
  std::fprintf(stderr, "bench: wrote %s in %.1f min%s\n", command.out_dir.c_str(), minutes,
               interrupted() ? " (interrupted)" : "");
  // instabilities are findings written to the tables, not a failed bench
  return interrupted() ? kExitInterrupted : kExitOk;
}

}  // namespace chainmail

#include "bench/harness/suites.hpp"

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

#include "bench/harness/commands.hpp"
#include "bench/harness/output.hpp"
#include "bench/harness/render_output.hpp"

namespace chainmail {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

std::string shell_quote(const std::string& s) {
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
  auto job_line = [&](size_t k) {
    std::string line = shell_quote(exe) + " run " + shell_quote(command.scene_file) +
                       " --backends " + points[k].backend + " --out " +
                       shell_quote(out + "/points/" + std::to_string(k)) + " --cache " +
                       shell_quote(command.cache_dir) + " --quiet";
    for (const auto& s : points[k].sets) line += " --set " + shell_quote(s);
    return line;
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
    for (size_t k = 0; k < points.size(); ++k) std::printf("%s\n", job_line(k).c_str());
    return kExitOk;
  }

  // the reference run once, before the points share it through the cache
  RunOptions reference_options;
  reference_options.progress = command.progress;
  reference_options.cache_dir = command.cache_dir;
  std::vector<std::string> reference_sets = command.overrides;
  reference_sets.push_back(reference_set);
  const Scene reference_scene = load_scene_file(command.scene_file, reference_sets);
  reference_frames(reference_scene, make_weave(base.weave, base.ring), reference_options, nullptr);

  fs::create_directories(out + "/points");
  std::mutex print;
  std::atomic<int> done{0};
  run_parallel(static_cast<int>(points.size()), command.jobs, [&](int k) {
    // a point's old results must never stand in for a run that failed
    std::error_code ignored;
    fs::remove_all(out + "/points/" + std::to_string(k), ignored);
    const std::string line =
        job_line(k) + " >" + shell_quote(out + "/points/" + std::to_string(k) + ".log") + " 2>&1";
    std::system(line.c_str());
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
    std::ifstream in(out + "/points/" + std::to_string(k) + "/summary.json");
    json summary = json::parse(in, nullptr, false);
    if (summary.is_discarded() || !summary["backends"].contains(p.backend)) {
      csv << ",,,,,false,error\n";
      ++unstable;
      continue;
    }
    const json& b = summary["backends"][p.backend];
    // cost per simulated second of what was simulated: an unstable run stops early
    const double simulated = b["steps"].get<double>() * b["dt"].get<double>();
    const double duration =
        simulated > 0.0 ? simulated : summary["scene"]["duration"].get<double>();
    const double error =
        b["final"].contains("drape_rms") ? b["final"]["drape_rms"].get<double>() : NAN;
    const double cat = b.contains("catenary_error") ? b["catenary_error"].get<double>() : NAN;
    csv << ',' << csv_number(b["wall_s"].get<double>() / duration) << ','
        << csv_number(b["ms_per_step"].get<double>()) << ',' << csv_number(error) << ','
        << csv_number(cat) << ',' << (b["stable"].get<bool>() ? "true" : "false") << ','
        << b["verdict"].get<std::string>() << '\n';
    unstable += !b["stable"].get<bool>();
  }
  write_file_atomic(out + "/sweep.csv", csv.str());
  make_plot("plot_sweep.py", {out + "/sweep.csv", out + "/sweep.png", base.name});
  std::fprintf(stderr, "wrote %s/sweep.csv (%zu points, %d unstable)\n", out.c_str(), points.size(),
               unstable);
  return kExitOk;
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
    return run.stable || run.verdict == "watchdog";  // too slow to finish is not unstable
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
  options.keep_frames = false;
  options.other_pair_metrics = true;
  options.max_wall_seconds = command.max_wall_seconds;
  RunOptions search = options;
  search.other_pair_metrics = false;

  std::ostringstream csv, md;
  csv << "case,backend,dt,verdict,largest_stable_dt,bound,max_stretch,broken_links,"
         "penetrating_linked,false_links,max_speed,ms_per_step\n";
  md << "# Stability suite\n\nEach case runs every backend at its default knobs (the verdict), "
        "then bisects for the largest stable dt (log-space, 3 steps, 6 for the spring study; "
        "`>=` = stable at the top of the searched range, `<` = unstable at the bottom).\n\n"
        "| case | backend | dt (s) | verdict | largest stable dt (s) | max_stretch | "
        "broken_links | penetrating_linked | max_speed (m/s) |\n"
        "|---|---|---|---|---|---|---|---|---|\n";
  int unstable = 0;
  for (const StabilityCase& c : stability_cases(command.quick)) {
    const Scene scene = scene_from_json(c.scene, "stability/" + c.name);
    const Weave weave = make_weave(scene.weave, scene.ring);
    std::vector<std::string> names =
        c.only.empty()
            ? select_backends(scene, command.backends.empty() ? std::vector<std::string>{"all"}
                                                              : command.backends)
            : c.only;
    for (const auto& name : names) {
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
      const DtSearch dt =
          largest_stable_dt(scene, weave, name, run.dt, run.stable, c.bisection_steps, search);
      const Metrics& m = run.final_metrics();
      unstable += !run.stable;
      csv << c.name << ',' << name << ',' << csv_number(run.dt) << ',' << run.verdict << ','
          << csv_number(dt.largest) << ',' << dt.bound << ',' << csv_number(m.max_stretch) << ','
          << m.broken_links << ',' << m.penetrating_linked << ',' << m.false_links << ','
          << csv_number(m.max_speed) << ',' << csv_number(run.ms_per_step()) << '\n';
      char line[512];
      std::snprintf(line, sizeof line,
                    "| %s | %s | %g | %s | %s %g | %.4g | %lld | %lld | %.3g |\n", c.name.c_str(),
                    name.c_str(), run.dt, run.verdict.c_str(),
                    dt.bound == "=" ? "" : dt.bound.c_str(), dt.largest, m.max_stretch,
                    m.broken_links, m.penetrating_linked, m.max_speed);
      md << line;
    }
  }
  md << "\nCases:\n\n";
  for (const StabilityCase& c : stability_cases(command.quick))
    md << "- `" << c.name << "`: " << c.description << "\n";
  write_file_atomic(command.out_dir + "/stability.csv", csv.str());
  write_file_atomic(command.out_dir + "/stability.md", md.str());
  std::fprintf(stderr, "wrote %s/stability.{csv,md} (%d unstable at default settings)\n",
               command.out_dir.c_str(), unstable);
  return kExitOk;  // instabilities are the suite's findings, not a failure of the suite
}

}  // namespace chainmail

// ---------------------------------------------------------------------------------------------
// the main bench

namespace chainmail {

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
  const std::string out = command.out_dir;
  const auto started = std::chrono::steady_clock::now();
  // reference runs are cached by scene and knobs, not by build: a bench starts with an empty cache
  // so that a changed backend is never measured against its old self
  std::error_code ignored;
  fs::remove_all(out + "/.cache", ignored);
  std::function<void(const SceneRun&, const std::string&)> render;
  if (command.render) {
    try {
      render = make_render_writer("");
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
             "`catenary` is the chain's sag error against the analytic catenary.\n\n"
             "| scene | backend | max_stretch | mean_stretch | penetrating_linked | "
             "penetrating_other | "
             "broken_links | false_links | drape_rms (mm) | drape_coefficient | catenary |\n"
             "|---|---|---|---|---|---|---|---|---|---|---|\n";
  bool all_stable = true;
  for (const BenchScene& b : set) {
    const Scene scene = load_scene_file(scenes + b.file, command.quick ? b.quick : b.full);
    RunOptions options;
    options.backends =
        command.backends.empty() ? std::vector<std::string>{"all"} : command.backends;
    options.progress = command.progress;
    options.cache_dir = out + "/.cache";
    const SceneRun run = run_scene(scene, options);
    all_stable &= run.all_stable();
    OutputOptions output;
    if (render) {
      // the final frame only keeps results/ small
      output.render = [&](const SceneRun& r, const std::string& folder) {
        SceneRun last = r;
        for (auto& br : last.runs) {
          if (!br.frames.empty()) br.frames = {br.frames.back()};
        }
        render(last, folder);
      };
    }
    write_run_folder(run, out + "/" + scene.name, output);

    double plausible_cost = 0.0;
    for (const auto& r : run.runs) {
      if (r.name == "plausible") plausible_cost = r.ms_per_step() / r.dt;
    }
    for (const auto& r : run.runs) {
      char line[512];
      const double relative = plausible_cost > 0 ? (r.ms_per_step() / r.dt) / plausible_cost : NAN;
      std::snprintf(line, sizeof line, "| %s | %d | %s | %g | %.3f | %.2f | %s | %s |\n",
                    scene.name.c_str(), run.weave.size(), r.name.c_str(), r.dt, r.ms_per_step(),
                    r.realtime_factor(),
                    std::isnan(relative) ? "-" : (table_number(relative, 3) + "x").c_str(),
                    r.verdict.c_str());
      timing << line;
      timing_csv << scene.name << ',' << run.weave.size() << ',' << r.name << ','
                 << csv_number(r.dt) << ',' << r.steps << ',' << csv_number(r.ms_per_step()) << ','
                 << csv_number(r.realtime_factor()) << ',' << r.verdict << ',' << std::hex << r.hash
                 << std::dec << '\n';
      const Metrics& m = r.final_metrics();
      std::snprintf(
          line, sizeof line,
          "| %s | %s | %.4f | %.4f | %lld | %lld | %lld | %lld | %s | %s | %s |\n",
          scene.name.c_str(), r.name.c_str(), m.max_stretch, m.mean_stretch, m.penetrating_linked,
          m.penetrating_other, m.broken_links, m.false_links,
          m.drape_rms ? table_number(1e3 * *m.drape_rms, 3).c_str() : "-",
          m.drape_coefficient ? table_number(*m.drape_coefficient, 3).c_str() : "-",
          r.catenary_error ? (table_number(100.0 * *r.catenary_error, 3) + " %").c_str() : "-");
      metrics << line;
    }
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
    sweep.cache_dir = out + "/.cache";
    sweep_command(sweep);
  }

  // stiff and extreme cases
  StabilityCommand stability;
  stability.backends = command.backends;
  stability.out_dir = out + "/stability";
  stability.quick = command.quick;
  stability.max_wall_seconds = command.quick ? 5.0 : 10.0;
  stability.progress = command.progress;
  stability_command(stability);

  std::ostringstream readme;
  readme
      << "# Results of `chainmail bench`\n\n"
         "Regenerate with `./scripts/bench.sh` (or `chainmail bench --out results`). Every scene "
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
         "- `curtain_30x30/` and `shaders/` come from their own commands, not from `bench`: "
         "the curtain at the paper's size in every backend, rendered side by side "
         "(`scripts/gallery.sh`), and one picture per cloth shader (`scripts/shaders.sh`).\n"
         "- `micro_render.csv` — the renderer's ms per frame at 1280x720 (900 and 10,000 rings, "
         "with and without level of detail, 4x MSAA and none) from `scripts/render_bench.sh`, not "
         "from `bench`.\n";
  const double minutes =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() / 60.0;
  char took[96];
  std::snprintf(took, sizeof took, "\nThis bench took %.1f minutes.\n", minutes);
  readme << took;
  write_file_atomic(out + "/README.md", readme.str());
  std::fprintf(stderr, "bench: wrote %s in %.1f min\n", out.c_str(), minutes);
  (void)all_stable;  // instabilities are findings written to the tables, not a failed bench
  return kExitOk;
}

}  // namespace chainmail

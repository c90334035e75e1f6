#include "bench/harness/output.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace chainmail {
namespace fs = std::filesystem;

std::string csv_number(double value) {
  if (std::isnan(value)) return "";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", value);
  return buffer;
}

std::string table_number(double value, int significant) {
  if (std::isnan(value)) return "-";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.*g", significant, value);
  return buffer;
}

void write_file_atomic(const std::string& path, const std::string& text) {
  if (fs::path(path).has_parent_path()) fs::create_directories(fs::path(path).parent_path());
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.flush();
    if (!out) throw std::runtime_error("cannot write " + tmp);
  }
  fs::rename(tmp, path);
}

void write_folder_atomic(const std::string& path,
                         const std::function<void(const std::string&)>& fill) {
  const fs::path target(path);
  const std::string pid = std::to_string(::getpid());
  const fs::path staging = target.string() + ".partial-" + pid;
  const fs::path old = target.string() + ".old-" + pid;
  fs::remove_all(staging);
  fs::create_directories(staging);
  try {
    fill(staging.string());
  } catch (...) {
    fs::remove_all(staging);
    throw;
  }
  if (fs::exists(target)) fs::rename(target, old);
  fs::rename(staging, target);
  fs::remove_all(old);
}

nlohmann::json summary_json(const SceneRun& run) {
  nlohmann::json out;
  out["scene"] = run.scene.resolved;
  out["ring"] = {{"wire_radius", run.scene.ring.wire_radius},
                 {"centre_radius", run.scene.ring.centre_radius},
                 {"mass", run.scene.ring.mass()},
                 {"count", run.weave.size()}};
  if (run.reference_note) out["reference"] = *run.reference_note;
  nlohmann::json backends = nlohmann::json::object();
  for (const BackendRun& b : run.runs) {
    nlohmann::json entry;
    entry["dt"] = b.dt;
    entry["steps"] = b.steps;
    entry["wall_s"] = b.wall_s;
    entry["ms_per_step"] = b.ms_per_step();
    entry["realtime_factor"] = b.realtime_factor();
    entry["stable"] = b.stable;
    entry["verdict"] = b.verdict;
    char hash[17];
    std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(b.hash));
    entry["hash"] = hash;
    nlohmann::json final_metrics = nlohmann::json::object();
    const Metrics& m = b.final_metrics();
    for (const auto& name : metric_names()) {
      const double v = metric_value(m, name);
      if (!std::isnan(v)) final_metrics[name] = v;  // absent metrics stay absent, never zero
    }
    final_metrics["non_finite"] = m.non_finite;
    entry["final"] = final_metrics;
    if (b.catenary_error) entry["catenary_error"] = *b.catenary_error;
    nlohmann::json knobs = nlohmann::json::object();
    for (const auto& [k, v] : b.knobs) knobs[k] = v;
    entry["knobs"] = knobs;
    nlohmann::json stages = nlohmann::json::object();
    for (const auto& [stage, stats] : b.stages) {
      stages[stage] = {{"calls", stats.calls}, {"ms", 1e3 * stats.seconds}};
    }
    entry["stages"] = stages;
    backends[b.name] = entry;
  }
  out["backends"] = backends;
  return out;
}

std::string metrics_csv(const SceneRun& run) {
  std::ostringstream out;
  out << "backend,t";
  for (const auto& name : metric_names()) out << ',' << name;
  out << ",step_wall_ms\n";
  for (const BackendRun& b : run.runs) {
    for (const Sample& s : b.samples) {
      out << b.name << ',' << csv_number(s.t);
      for (const auto& name : metric_names())
        out << ',' << csv_number(metric_value(s.metrics, name));
      out << ',' << csv_number(s.step_wall_ms) << '\n';
    }
  }
  return out.str();
}

std::string table_markdown(const SceneRun& run) {
  std::ostringstream out;
  const Scene& scene = run.scene;
  out << "# " << scene.name << "\n\n";
  if (!scene.description.empty()) out << scene.description << "\n\n";
  out << run.weave.size() << " rings (" << to_string(scene.weave.type) << ", " << scene.weave.rows
      << " x " << scene.weave.cols << "), " << scene.duration << " s simulated";
  if (run.reference_note) out << "; " << *run.reference_note;
  out << ".\n\n";

  double plausible_ms = 0.0;
  for (const auto& b : run.runs) {
    if (b.name == "plausible") plausible_ms = b.ms_per_step() / b.dt;
  }
  out << "| backend | dt (s) | ms/step | real-time factor | cost vs plausible | verdict |"
         " max_stretch | mean_stretch | penetrating_linked | penetrating_other | broken_links |"
         " false_links | drape_rms (mm) | drape_coefficient |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  char line[1024];
  for (const auto& b : run.runs) {
    const Metrics& m = b.final_metrics();
    // cost per simulated second relative to plausible's
    const double relative = plausible_ms > 0 ? (b.ms_per_step() / b.dt) / plausible_ms : NAN;
    std::snprintf(
        line, sizeof line,
        "| %s | %g | %.3f | %.2f | %s | %s | %.4f | %.4f | %lld | %lld | %lld | %lld | %s "
        "| %s |\n",
        b.name.c_str(), b.dt, b.ms_per_step(), b.realtime_factor(),
        std::isnan(relative) ? "-" : (table_number(relative, 3) + "x").c_str(), b.verdict.c_str(),
        m.max_stretch, m.mean_stretch, m.penetrating_linked, m.penetrating_other, m.broken_links,
        m.false_links, m.drape_rms ? table_number(1e3 * *m.drape_rms, 3).c_str() : "-",
        m.drape_coefficient ? table_number(*m.drape_coefficient, 3).c_str() : "-");
    out << line;
  }
  out << "\nms/step counts `step()` only; real-time factor = simulated / wall seconds.\n";
  return out.str();
}

std::string frame_csv(const RingFrame& frame, const Weave& weave) {
  std::ostringstream out;
  out << "ring,i,j,x,y,z,qw,qx,qy,qz\n";
  char line[320];
  for (int r = 0; r < frame.size(); ++r) {
    std::snprintf(line, sizeof line, "%d,%d,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", r,
                  weave.grid[r][0], weave.grid[r][1], frame.position(0, r), frame.position(1, r),
                  frame.position(2, r), frame.orientation(0, r), frame.orientation(1, r),
                  frame.orientation(2, r), frame.orientation(3, r));
    out << line;
  }
  return out.str();
}

void write_run_folder(const SceneRun& run, const std::string& folder,
                      const OutputOptions& options) {
  write_folder_atomic(folder, [&](const std::string& staging) {
    write_file_atomic(staging + "/summary.json", summary_json(run).dump(2) + "\n");
    write_file_atomic(staging + "/metrics.csv", metrics_csv(run));
    write_file_atomic(staging + "/table.md", table_markdown(run));
    if (options.frames) {
      for (const BackendRun& b : run.runs) {
        for (size_t k = 0; k < b.frames.size(); ++k) {
          char name[32];
          std::snprintf(name, sizeof name, "/%05zu.csv", k);
          write_file_atomic(staging + "/frames/" + b.name + name,
                            frame_csv(b.frames[k], run.weave));
        }
      }
    }
    if (options.render) options.render(run, staging + "/images");
  });
}

}  // namespace chainmail

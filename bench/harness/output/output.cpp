#include "bench/harness/output/output.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "backends/backend.hpp"
#include "bench/harness/common/version.hpp"
#include "bench/harness/output/frame_stream.hpp"
#include "bench/harness/output/number_format.hpp"
#include "bench/harness/output/output_error.hpp"
#include "bench/harness/output/table_cells.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace fs = std::filesystem;

void write_file_atomic(const std::string& path, const std::string& text) {
  if (fs::path(path).has_parent_path()) fs::create_directories(fs::path(path).parent_path());
  const std::string tmp = path + ".tmp";
  {
    errno = 0;
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.flush();
    if (!out) throw_write_error(tmp, errno);
  }
  fs::rename(tmp, path);
}

namespace {

// the optional metrics: left out of "final" when a run has none, never written as zero
struct OptionalMetric {
  const char* name;
  std::optional<double> Metrics::*value;
};
constexpr OptionalMetric kOptionalMetrics[] = {{"drape_rms", &Metrics::drape_rms},
                                               {"drape_coefficient", &Metrics::drape_coefficient}};

bool absent(const Metrics& m, const std::string& name) {
  for (const OptionalMetric& optional : kOptionalMetrics) {
    if (name == optional.name) return !(m.*optional.value).has_value();
  }
  return false;
}

}  // namespace

nlohmann::json metrics_json(const Metrics& m) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& name : metric_names()) {
    // absent metrics stay absent, never zero; failed ones (inf, NaN of a blown-up run) are null
    if (!absent(m, name)) out[name] = json_number(metric_value(m, name));
  }
  out["non_finite"] = m.non_finite;
  return out;
}

namespace {

nlohmann::json backend_entry(const BackendRun& b) {
  nlohmann::json entry;
  entry["dt"] = b.dt;
  entry["steps"] = b.steps;
  entry["wall_s"] = b.wall_s;
  entry["ms_per_step"] = b.ms_per_step();
  entry["realtime_factor"] = b.realtime_factor();
  entry["stable"] = b.stable;
  entry["verdict"] = to_string(b.verdict);
  char hash[17];
  std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(b.hash));
  entry["hash"] = b.started() ? nlohmann::json(hash) : nlohmann::json(nullptr);
  entry["samples"] = b.samples;
  entry["settled"] = b.settled ? nlohmann::json(*b.settled) : nlohmann::json(nullptr);
  entry["overstretched"] =
      b.overstretched ? nlohmann::json(*b.overstretched) : nlohmann::json(nullptr);
  entry["peak_stretch"] = b.started() ? json_number(b.peak_stretch) : nlohmann::json(nullptr);
  entry["final"] = b.started() ? metrics_json(b.final_metrics()) : nlohmann::json::object();
  if (b.catenary_error) entry["catenary_error"] = json_number(*b.catenary_error);
  nlohmann::json knobs = nlohmann::json::object();
  const BackendInfo* info = find_backend(b.name);
  for (const auto& [k, v] : b.knobs) {
    const KnobSpec* spec = info ? find_knob(*info, k) : nullptr;
    // a choice as its name, as the scene gives it
    knobs[k] = spec && spec->type == KnobSpec::Type::choice ? nlohmann::json(choice_name(*spec, v))
                                                            : nlohmann::json(v);
  }
  entry["knobs"] = knobs;
  nlohmann::json stages = nlohmann::json::object();
  for (const auto& [stage, stats] : b.stages) {
    stages[stage] = {{"calls", stats.calls}, {"ms", 1e3 * stats.seconds}};
  }
  entry["stages"] = stages;
  if (b.residual.steps > 0) {
    const ResidualStats& r = b.residual;
    entry["residual"] = {{"last", json_number(r.last)},
                         {"max", json_number(r.max)},
                         {"tolerance", r.tolerance},
                         {"steps", r.steps},
                         {"unconverged_steps", r.unconverged}};
  }
  return entry;
}

}  // namespace

nlohmann::json summary_json(const SceneRun& run) {
  nlohmann::json out;
  out["scene"] = scene_to_json(run.scene);
  out["ring"] = {{"wire_radius", run.scene.ring.wire_radius},
                 {"centre_radius", run.scene.ring.centre_radius},
                 {"mass", run.scene.ring.mass()},
                 {"count", run.weave.size()}};
  out["build"] = {
      {"version", chainmail_version()},   {"commit", chainmail_commit()},
      {"compiler", chainmail_compiler()}, {"build_type", chainmail_build_type()},
      {"threads", run.threads},           {"host_cores", std::thread::hardware_concurrency()}};
  if (run.reference_note) out["reference"] = *run.reference_note;
  out["interrupted"] = run.interrupted;
  nlohmann::json backends = nlohmann::json::object();
  for (const BackendRun& b : run.runs) backends[b.name] = backend_entry(b);
  out["backends"] = backends;
  return out;
}

std::string metrics_header() {
  std::string header = "backend,t";
  for (const auto& name : metric_names()) header += "," + name;
  return header + ",step_wall_ms\n";
}

std::string metrics_row(const std::string& backend, const Sample& s) {
  std::string row = backend + "," + csv_number(s.t);
  // appended in two parts: "," + a temporary trips a false -Wrestrict in g++ 12
  for (const auto& name : metric_names())
    row.append(",").append(csv_number(metric_value(s.metrics, name)));
  return row + "," + csv_number(s.step_wall_ms) + "\n";
}

std::string table_markdown(const SceneRun& run) {
  std::ostringstream out;
  const Scene& scene = run.scene;
  const double a = scene.ring.wire_radius;
  out << "# " << scene.name << "\n\n";
  if (!scene.description.empty()) out << scene.description << "\n\n";
  out << run.weave.size() << " rings (" << to_string(scene.weave.type) << ", " << scene.weave.rows
      << " x " << scene.weave.cols << "), " << scene.duration << " s simulated";
  if (run.reference_note) out << "; " << *run.reference_note;
  out << ".\n\n";

  const double plausible_ms = plausible_cost(run.runs);
  bool catenary = false;
  for (const auto& b : run.runs) catenary |= b.catenary_error.has_value();
  out << "| backend | dt (s) | ms/step | real-time factor | cost vs plausible | verdict | settled |"
         " overstretched | max_stretch | mean_stretch | penetrating_linked | depth max/mean "
         "linked (a) | penetrating_other | depth max/mean other (a) | broken_links | false_links |"
         " drape_rms (mm) | drape_coefficient |"
      << (catenary ? " catenary sag error |" : "") << "\n";
  out << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
      << (catenary ? "---|" : "") << "\n";
  for (const auto& b : run.runs) {
    out << "| " << b.name << " | " << timing_cells(b, plausible_ms) << " | " << to_string(b.verdict)
        << " | " << yes_no_cell(b.settled) << " | " << yes_no_cell(b.overstretched) << " | "
        << (b.started() ? final_metric_cells(b.final_metrics(), a) : missing_metric_cells())
        << " |";
    if (catenary) out << " " << (b.started() ? catenary_cell(b.catenary_error) : "-") << " |";
    out << "\n";
  }
  out << "\nms/step counts `step()` only; real-time factor = simulated / wall seconds. Depths are "
         "2a minus the centre-circle distance of interpenetrating pairs, in wire radii a. "
         "settled: kinetic energy at the end below "
      << table_number(100.0 * kSettledEnergyFraction, 3)
      << " % of the energy released; overstretched: a link's stretch went above "
      << table_number(1.0 + kOverstretchTolerance, 4)
      << " at some sample (impossible for real rings).\n";
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

void round_as_csv(RingFrame& frame) {
  const auto round = [](double& value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", value);
    value = std::strtod(text, nullptr);
  };
  round(frame.t);
  for (Eigen::Index k = 0; k < frame.position.size(); ++k) round(frame.position.data()[k]);
  for (Eigen::Index k = 0; k < frame.orientation.size(); ++k) round(frame.orientation.data()[k]);
}

void write_run_folder(const SceneRun& run, const std::string& folder,
                      const OutputOptions& options) {
  fs::create_directories(folder);
  write_file_atomic(folder + "/summary.json", summary_json(run).dump(2) + "\n");
  // metrics.csv: the rows each backend streamed, in the order of the runs
  {
    const std::string path = folder + "/metrics.csv";
    errno = 0;
    std::ofstream out(path + ".tmp", std::ios::binary);
    out << metrics_header();
    for (const BackendRun& b : run.runs) {
      std::ifstream rows(folder + "/.streams/" + b.name + ".csv", std::ios::binary);
      if (rows && rows.peek() != std::ifstream::traits_type::eof()) out << rows.rdbuf();
    }
    out.flush();
    if (!out) throw_write_error(path, errno);
    out.close();
    fs::rename(path + ".tmp", path);
  }
  write_file_atomic(folder + "/table.md", table_markdown(run));
  if (options.render && !run.interrupted) options.render(run, folder + "/images");
  // exports at full precision, also of what an interrupted run finished
  for (const BackendRun& b : run.runs) {
    if (options.exports.empty() || b.stream.empty()) continue;
    auto reader = FrameReader::open(b.stream, run.weave.size());
    if (!reader) continue;
    write_exports({run.scene, run.weave, b.name}, stream_sequence(std::move(*reader)),
                  options.exports, folder + "/export");
  }
  std::error_code ignored;
  fs::remove_all(folder + "/.streams", ignored);
}

}  // namespace chainmail

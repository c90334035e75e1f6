// `chainmail sweep --gather DIR`: the points of a sweep that ran elsewhere (GNU parallel, Slurm)
// read back from DIR/points/K into DIR/sweep.csv and the plot, as a local sweep writes them.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "bench/harness/commands/commands.hpp"
#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/output/output_folder.hpp"
#include "bench/harness/suites/process.hpp"
#include "bench/harness/suites/sweep_jobs.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// the files gather writes into DIR itself, beside points/
const std::vector<std::string> kGatherFiles = {"sweep.csv", "sweep.png"};

[[noreturn]] void refuse(const std::string& dir, const std::string& why) {
  throw UsageError("--gather '" + dir + "': " + why);
}

// "point K (backend, key=value ...)", for messages
std::string point_name(const SweepPoint& p, size_t k) {
  std::string name = "point " + std::to_string(k) + " (" + p.backend;
  for (const auto& s : p.sets) name += ", " + s;
  return name + ")";
}

// the first key where two resolved scenes differ, dotted ("" when equal)
std::string first_difference(const json& expected, const json& found) {
  const json patch = json::diff(expected, found);
  if (patch.empty()) return "";
  std::string key = patch[0]["path"].get<std::string>().substr(1);
  for (auto& c : key) c = c == '/' ? '.' : c;
  return key;
}

// point k's folder must hold a complete run of this very point, written by chainmail
void check_point(const SweepCommand& command, const SweepPlan& plan, size_t k) {
  const SweepPoint& p = plan.points[k];
  const std::string folder = command.gather + "/points/" + std::to_string(k);
  if (!fs::exists(folder + "/summary.json"))
    refuse(command.gather, point_name(p, k) + " is missing: no points/" + std::to_string(k) +
                               "/summary.json (not run yet, or it failed: see its log)");
  if (const std::string why = replace_refusal(folder, "run", false); !why.empty())
    refuse(command.gather, "points/" + std::to_string(k) + " " + why);
  std::ifstream in(folder + "/summary.json");
  const json summary = json::parse(in, nullptr, false);
  if (summary.is_discarded() || !summary.contains("scene") || !summary.contains("backends"))
    refuse(command.gather, "points/" + std::to_string(k) + "/summary.json is not a run summary");
  std::vector<std::string> sets = command.overrides;
  sets.insert(sets.end(), p.sets.begin(), p.sets.end());
  sets.push_back(plan.jobs.reference_set);
  const json expected = scene_to_json(load_scene_file(command.scene_file, sets));
  std::string ran;
  for (const auto& [name, entry] : summary["backends"].items())
    ran += (ran.empty() ? "" : ",") + name;
  if (ran != p.backend)
    refuse(command.gather, "points/" + std::to_string(k) + " is from another sweep: it ran " + ran +
                               ", this sweep's " + point_name(p, k) + " runs " + p.backend);
  if (const std::string key = first_difference(expected, summary["scene"]); !key.empty())
    refuse(command.gather, "points/" + std::to_string(k) +
                               " is from another sweep: its scene differs at '" + key +
                               "' from this sweep's " + point_name(p, k));
}

// DIR may hold no more points than the sweep has, and nothing gather writes that chainmail did
// not write before
void check_folder(const SweepCommand& command, const SweepPlan& plan) {
  const std::string& dir = command.gather;
  if (!fs::is_directory(dir)) refuse(dir, "not a folder");
  const std::string extra = dir + "/points/" + std::to_string(plan.points.size());
  if (fs::exists(extra))
    refuse(dir, "holds points/" + std::to_string(plan.points.size()) + ": it is from another " +
                    "sweep (this one has " + std::to_string(plan.points.size()) + " points)");
  std::string made_by;
  std::set<std::string> listed;
  const bool has_manifest = read_manifest(dir, made_by, listed);
  if (has_manifest && made_by != "sweep")
    refuse(dir, "holds the output of 'chainmail " + made_by + "', not a sweep's points");
  if (!has_manifest && fs::exists(fs::symlink_status(fs::path(dir) / kManifestName)))
    refuse(dir, std::string("holds a ") + kManifestName + " chainmail did not write");
  for (const auto& name : kGatherFiles) {
    if (fs::exists(fs::symlink_status(fs::path(dir) / name)) && !listed.count(name))
      refuse(dir, "holds '" + name + "', which chainmail did not write: refusing to replace it");
  }
}

// the sweep's manifest: the files gather wrote and every point's own (listed in its manifest)
std::vector<std::string> gathered_files(const std::string& dir, size_t points) {
  std::string made_by;
  std::set<std::string> before;  // a local sweep's logs, say: still chainmail's
  read_manifest(dir, made_by, before);
  std::vector<std::string> files;
  for (const auto& name : kGatherFiles) before.insert(name);
  for (const auto& name : before) {
    if (name.rfind("points/", 0) != 0 || name.ends_with(".log")) {
      if (fs::exists(fs::path(dir) / name)) files.push_back(name);
    }
  }
  for (size_t k = 0; k < points; ++k) {
    const std::string folder = "points/" + std::to_string(k);
    std::string made_by;
    std::set<std::string> listed;
    read_manifest(dir + "/" + folder, made_by, listed);
    for (const auto& f : listed) files.push_back(folder + "/" + f);
    files.push_back(folder + "/" + kManifestName);
  }
  std::sort(files.begin(), files.end());
  files.erase(std::unique(files.begin(), files.end()), files.end());
  return files;
}

}  // namespace

int gather_sweep(const SweepCommand& command, const SweepPlan& plan) {
  const std::string& dir = command.gather;
  check_folder(command, plan);
  for (size_t k = 0; k < plan.points.size(); ++k) check_point(command, plan, k);
  const int unstable = write_sweep_csv(plan.axes, plan.points, dir);
  make_plot("plot_sweep.py", {dir + "/sweep.csv", dir + "/sweep.png", plan.base.name});
  write_manifest(dir, "sweep", gathered_files(dir, plan.points.size()));
  std::fprintf(stderr, "gathered %s/sweep.csv (%zu points, %d unstable)\n", dir.c_str(),
               plan.points.size(), unstable);
  return kExitOk;
}

}  // namespace chainmail

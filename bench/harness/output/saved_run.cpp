#include "bench/harness/output/saved_run.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bench/harness/common/usage_error.hpp"
#include "scene_file/scene_file.hpp"
#include "scene_file/scene_file_text.hpp"

namespace chainmail {
namespace {

constexpr const char* kFrameHeader = "ring,i,j,x,y,z,qw,qx,qy,qz";
constexpr long long kMaxSummaryBytes = 64LL << 20;

bool regular_file(const std::string& path) {
  struct stat info {};
  return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

std::string frame_path(const std::string& run, const std::string& backend, std::size_t k) {
  char name[32];
  std::snprintf(name, sizeof name, "/%05zu.csv", k);
  return run + "/frames/" + backend + name;
}

// one finite number of a CSV cell, all of it
bool parse_number(const std::string& cell, double& value) {
  if (cell.empty()) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtod(cell.c_str(), &end);
  return end == cell.c_str() + cell.size() && errno == 0 && std::isfinite(value);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream stream(line);
  for (std::string cell; std::getline(stream, cell, ',');) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

// the scene and each backend's ms per step from summary.json
nlohmann::json read_summary(const std::string& run) {
  const std::string path = run + "/summary.json";
  if (!regular_file(path))
    throw UsageError(shown(run) + ": not a run folder (no summary.json; see chainmail run)");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (text.str().size() > kMaxSummaryBytes) throw UsageError(shown(path) + ": too large");
  nlohmann::json summary = nlohmann::json::parse(text.str(), nullptr, false);
  if (summary.is_discarded() || !summary.is_object() || !summary.contains("scene") ||
      !summary.contains("backends") || !summary["backends"].is_object())
    throw UsageError(shown(path) + ": not a summary chainmail wrote (no scene or backends)");
  return summary;
}

// backends in the order of metrics.csv, each with its samples' times
std::vector<SavedBackend> read_metrics(const std::string& run) {
  const std::string path = run + "/metrics.csv";
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!regular_file(path) || !std::getline(in, line) || line.rfind("backend,t,", 0) != 0)
    throw UsageError(shown(path) + ": missing, or not the metrics chainmail wrote");
  std::vector<SavedBackend> backends;
  for (int number = 2; std::getline(in, line); ++number) {
    const std::vector<std::string> cells = split(line);
    double t = 0.0;
    if (cells.size() < 2 || cells[0].empty() || !parse_number(cells[1], t))
      throw UsageError(shown(path) + ": line " + std::to_string(number) + ": no backend and time");
    if (backends.empty() || backends.back().name != cells[0]) {
      backends.emplace_back();
      backends.back().name = cells[0];
    }
    backends.back().times.push_back(t);
  }
  return backends;
}

}  // namespace

void read_frame_csv(const std::string& path, int rings, RingFrame& frame) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!std::getline(in, line) || line != kFrameHeader)
    throw UsageError(shown(path) + ": line 1: not the frame header " + kFrameHeader);
  frame.resize(rings);
  frame.velocity.setZero();
  for (int ring = 0; ring < rings; ++ring) {
    const std::string where = shown(path) + ": line " + std::to_string(ring + 2) + ": ";
    if (!std::getline(in, line)) throw UsageError(where + "missing (one row per ring)");
    const std::vector<std::string> cells = split(line);
    double value[10];
    bool ok = cells.size() == 10;
    for (int c = 0; ok && c < 10; ++c) ok = parse_number(cells[c], value[c]);
    if (!ok || value[0] != ring)
      throw UsageError(where + "expected ring " + std::to_string(ring) + " and 9 finite numbers");
    frame.position.col(ring) << value[3], value[4], value[5];
    frame.orientation.col(ring) << value[6], value[7], value[8], value[9];
  }
}

SavedRun read_saved_run(const std::string& path) {
  SavedRun run;
  run.path = path;
  const nlohmann::json summary = read_summary(path);
  run.scene = scene_from_json(summary["scene"], path + "/summary.json");
  run.weave = make_weave(run.scene.weave, run.scene.ring);
  run.backends = read_metrics(path);
  for (SavedBackend& b : run.backends) {
    if (!summary["backends"].contains(b.name))
      throw UsageError(shown(path) + ": backend '" + b.name + "' of metrics.csv not in summary");
    const nlohmann::json& entry = summary["backends"][b.name];
    if (entry.contains("ms_per_step") && entry["ms_per_step"].is_number())
      b.ms_per_step = entry["ms_per_step"].get<double>();
    while (b.frames < b.times.size() && regular_file(frame_path(path, b.name, b.frames)))
      ++b.frames;
  }
  return run;
}

FrameSequence SavedRun::frames(const SavedBackend& backend) const {
  FrameSequence sequence;
  sequence.count = backend.frames;
  sequence.read = [folder = path, name = backend.name, times = backend.times, rings = weave.size()](
                      std::size_t k, RingFrame& frame) {
    read_frame_csv(frame_path(folder, name, k), rings, frame);
    frame.t = times[k];
    return true;
  };
  return sequence;
}

}  // namespace chainmail

#include "bench/harness/report/report_data.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/output/saved_run.hpp"
#include "core/frame.hpp"
#include "scene_file/scene_file_text.hpp"

namespace chainmail {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// a table or summary larger than this is not one chainmail wrote for a page
constexpr std::uintmax_t kMaxFileBytes = 32ULL << 20;

std::string read_text(const fs::path& path) {
  std::error_code error;
  if (fs::file_size(path, error) > kMaxFileBytes || error)
    throw UsageError(shown(path.string()) + ": too large or unreadable for the report");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) throw UsageError(shown(path.string()) + ": unreadable");
  return text.str();
}

// a summary.json as chainmail writes it: an object with the scene and the backends
json read_summary(const fs::path& path) {
  json summary = json::parse(read_text(path), nullptr, false);
  if (summary.is_discarded() || !summary.is_object() || !summary.contains("scene") ||
      !summary["scene"].is_object() || !summary.contains("backends") ||
      !summary["backends"].is_object())
    throw UsageError(shown(path.string()) +
                     ": corrupt, or not a summary chainmail wrote (no scene or backends)");
  return summary;
}

// folders the page does not read: frames (read apart), sweep points, the page's own files
bool skipped(const fs::path& path) {
  const std::string name = path.filename().string();
  return name.empty() || name[0] == '.' || name == "frames" || name == "points" || name == "report";
}

// every summary, CSV table and image under `folder`, by path relative to it (sorted: the page
// lists scenes in this order)
void read_files(const fs::path& folder, json& files, json& images) {
  std::vector<fs::path> found;
  for (auto it = fs::recursive_directory_iterator(folder); it != fs::recursive_directory_iterator();
       ++it) {
    if (skipped(it->path())) {
      if (it->is_directory()) it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file()) found.push_back(fs::relative(it->path(), folder));
  }
  std::sort(found.begin(), found.end());
  for (const fs::path& rel : found) {
    const std::string ext = rel.extension().string();
    if (ext == ".png") images.push_back(rel.generic_string());
    if (ext == ".csv") files[rel.generic_string()] = read_text(folder / rel);
    if (rel.filename() == "summary.json") files[rel.generic_string()] = read_summary(folder / rel);
  }
}

// a CSV table the command must have written, with the header it writes
void require_table(const fs::path& folder, const json& files, const std::string& name,
                   const std::string& header) {
  const auto it = files.find(name);
  if (it == files.end())
    throw UsageError(shown((folder / name).string()) +
                     ": missing (not a folder this command wrote)");
  if (it->get<std::string>().rfind(header, 0) != 0)
    throw UsageError(shown((folder / name).string()) + ": corrupt (no header " + header + ")");
}

std::size_t frame_files(const fs::path& dir) {
  std::size_t count = 0;
  for (const auto& entry : fs::directory_iterator(dir)) count += entry.is_regular_file() ? 1 : 0;
  return count;
}

// frames/<backend>/ of a run: every folder a backend of the summary, holding one CSV per sample;
// `prefix` names the run's folder under report/frames/ ("" for a run, "<scene>/" in a bench)
std::vector<ReportFrames> run_frames(const fs::path& folder, const SavedRun& run,
                                     const json& summary, const std::string& prefix) {
  std::vector<ReportFrames> result;
  const fs::path frames = folder / "frames";
  if (!fs::is_directory(frames)) return result;
  for (const auto& entry : fs::directory_iterator(frames)) {
    const std::string name = entry.path().filename().string();
    const bool known = std::any_of(run.backends.begin(), run.backends.end(),
                                   [&](const SavedBackend& b) { return b.name == name; });
    if (!entry.is_directory() || !known)
      throw UsageError(shown(entry.path().string()) + ": frames of no backend in summary.json");
  }
  for (const SavedBackend& b : run.backends) {
    const fs::path dir = frames / b.name;
    if (!fs::is_directory(dir)) continue;
    const json& entry = summary["backends"][b.name];
    const std::size_t samples = entry.contains("samples") && entry["samples"].is_number_unsigned()
                                    ? entry["samples"].get<std::size_t>()
                                    : b.times.size();
    if (b.frames != b.times.size() || samples != b.times.size() || frame_files(dir) != b.frames)
      throw UsageError(shown(dir.string()) + ": " + std::to_string(frame_files(dir)) +
                       " frame files, but summary.json has " + std::to_string(samples) +
                       " samples (frames do not match the summary)");
    result.push_back({b.name, prefix + b.name, dir.string(), b.frames, b.times,
                      static_cast<int>(run.weave.size())});
  }
  return result;
}

// a run's frames, read as `render` reads them and checked, into `input`; returns what the page's
// data hold of them (null when the run kept none)
json read_run_frames(const fs::path& folder, const json& summary, const std::string& prefix,
                     ReportInput& input) {
  const SavedRun run = read_saved_run(folder.string());
  const std::vector<ReportFrames> frames = run_frames(folder, run, summary, prefix);
  if (frames.empty()) return nullptr;
  json backends = json::object();
  for (const ReportFrames& f : frames) {
    for (std::size_t k = 0; k < f.count; ++k) frame_script(f, k);  // checked now
    backends[f.backend] = {{"count", f.count}, {"times", f.times}, {"key", f.key}};
  }
  input.frames.insert(input.frames.end(), frames.begin(), frames.end());
  return {{"rings", static_cast<int>(run.weave.size())}, {"backends", backends}};
}

// a bench's scene folders that kept frames (<scene>/frames/), by folder name
void read_bench_frames(const fs::path& folder, ReportInput& input) {
  json scenes = json::object();
  for (const auto& [name, value] : input.data["files"].items()) {
    const fs::path path(name);
    if (path.filename() != "summary.json" || !value.is_object()) continue;
    const std::string scene = path.parent_path().generic_string();
    if (scene.empty() || scene.find('/') != std::string::npos) continue;  // sweep points etc.
    if (!fs::is_directory(folder / scene / "frames")) continue;
    json frames = read_run_frames(folder / scene, value, scene + "/", input);
    if (!frames.is_null()) scenes[scene] = std::move(frames);
  }
  input.data["scene_frames"] = std::move(scenes);
}

bool has_scene_summary(const json& files) {
  for (const auto& [name, value] : files.items()) {
    if (name.find('/') != std::string::npos && value.is_object()) return true;
  }
  return false;
}

}  // namespace

ReportInput read_report_input(const std::string& folder, const std::string& command) {
  ReportInput input;
  input.data = {{"kind", command},
                {"folder", fs::absolute(folder).lexically_normal().filename().string()},
                {"files", json::object()},
                {"images", json::array()},
                {"frames", nullptr}};
  read_files(folder, input.data["files"], input.data["images"]);
  const json& files = input.data["files"];
  if (command == "run") {
    // (a missing summary.json is named by read_saved_run)
    input.data["frames"] = read_run_frames(folder, input.data["files"]["summary.json"], "", input);
  } else if (command == "sweep") {
    require_table(folder, files, "sweep.csv", "backend,");
  } else if (command == "stability") {
    require_table(folder, files, "stability.csv", "case,backend,");
  } else if (command == "bench" && !has_scene_summary(files)) {
    throw UsageError(shown(folder) + ": no <scene>/summary.json (not a folder bench wrote)");
  } else if (command == "bench") {
    read_bench_frames(folder, input);
  }
  return input;
}

std::string frame_script(const ReportFrames& frames, std::size_t k) {
  char name[32];
  std::snprintf(name, sizeof name, "/%05zu.csv", k);
  RingFrame frame;
  read_frame_csv(frames.folder + name, frames.rings, frame);
  std::string text = "chainmailFrame(" + json(frames.key).dump() + "," + std::to_string(k) + "," +
                     json(frames.times[k]).dump() + ",[";
  text.reserve(text.size() + static_cast<std::size_t>(frames.rings) * 7 * 7);
  char number[32];
  for (int r = 0; r < frames.rings; ++r) {
    // integers: a micrometre on a metre-sized scene and 1e-4 of a quaternion are far below a
    // ring's wire, and 0.6 of the size of 7 significant digits (the bench keeps many frames)
    const double values[7] = {1e6 * frame.position(0, r),    1e6 * frame.position(1, r),
                              1e6 * frame.position(2, r),    1e4 * frame.orientation(0, r),
                              1e4 * frame.orientation(1, r), 1e4 * frame.orientation(2, r),
                              1e4 * frame.orientation(3, r)};
    for (int c = 0; c < 7; ++c) {
      const double v = std::isfinite(values[c]) ? std::round(values[c]) + 0.0 : 0.0;
      std::snprintf(number, sizeof number, r + c == 0 ? "%.0f" : ",%.0f", v);
      text += number;
    }
  }
  text += "]);\n";
  return text;
}

}  // namespace chainmail

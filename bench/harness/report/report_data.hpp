// What the report page shows, read from a results folder and checked before anything is written
// (bench/harness/report/report.hpp).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace chainmail {

struct ReportFrames {
  std::string backend;
  std::string key;     // its folder under report/frames/: <backend>, or <scene>/<backend> (bench)
  std::string folder;  // frames/<backend> of the run, the CSVs
  std::size_t count = 0;
  std::vector<double> times;
  int rings = 0;
};

struct ReportInput {
  // report/data.js: kind, files (path -> JSON or CSV text), images, frames (a run's),
  // scene_frames (a bench's, by scene folder)
  nlohmann::json data;
  std::vector<ReportFrames> frames;  // the saved frames, per run and backend; empty when none
};

// reads `folder` as the output of `command`; throws UsageError naming the file when it is not
// what that command writes (missing or corrupt summary.json, frames that do not match it, ...)
ReportInput read_report_input(const std::string& folder, const std::string& command);

// frame `k` of a backend as the page's script: chainmailFrame(key, k, t, [x,y,z,qw,qx,qy,qz,...])
// in integers, positions in micrometres and quaternions in 1e-4; throws UsageError naming the
// CSV and line when it is not `frames.rings` rows
std::string frame_script(const ReportFrames& frames, std::size_t k);

}  // namespace chainmail

// What the report page shows, read from a results folder and checked before anything is written
// (bench/harness/report.hpp).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace chainmail {

struct ReportFrames {
  std::string backend;
  std::string folder;  // frames/<backend>, the CSVs
  std::size_t count = 0;
  std::vector<double> times;
};

struct ReportInput {
  nlohmann::json data;  // report/data.js: kind, files (path -> JSON or CSV text), images, frames
  std::vector<ReportFrames> frames;  // a run's saved frames, per backend; empty when none
  int rings = 0;
};

// reads `folder` as the output of `command`; throws UsageError naming the file when it is not
// what that command writes (missing or corrupt summary.json, frames that do not match it, ...)
ReportInput read_report_input(const std::string& folder, const std::string& command);

// frame `k` of a backend as the page's script: chainmailFrame(backend, k, t, [x,y,z,qw,qx,qy,qz,
// ...]); throws UsageError naming the CSV and line when it is not `rings` rows
std::string frame_script(const ReportFrames& frames, std::size_t k, int rings);

}  // namespace chainmail

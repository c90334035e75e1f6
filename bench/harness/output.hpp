// Writing a run's results: summary.json, metrics.csv, table.md, frame CSVs (DESIGN.md contracts).
// Everything goes into a staging folder that replaces the destination in one rename, so an
// interrupted run never leaves a half-written result.
#pragma once

#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "bench/harness/run.hpp"

namespace chainmail {

// write `text` to `path` through a temporary file and a rename
void write_file_atomic(const std::string& path, const std::string& text);

// a folder filled by `fill(staging_path)`, then moved onto `path` (replacing what was there)
void write_folder_atomic(const std::string& path,
                         const std::function<void(const std::string&)>& fill);

nlohmann::json summary_json(const SceneRun& run);
std::string metrics_csv(const SceneRun& run);
std::string table_markdown(const SceneRun& run);
std::string frame_csv(const RingFrame& frame, const Weave& weave);

// the number formatting every CSV uses (empty for NaN: an absent metric)
std::string csv_number(double value);
// a number for a Markdown table: `significant` digits, "-" for NaN
std::string table_number(double value, int significant);

struct OutputOptions {
  bool frames = false;  // frames/<backend>/<NNNNN>.csv
  // draws images into <folder>/images; empty = no rendering
  std::function<void(const SceneRun&, const std::string& images_folder)> render;
};

// the whole DESIGN.md result folder for one run
void write_run_folder(const SceneRun& run, const std::string& folder, const OutputOptions& options);

}  // namespace chainmail

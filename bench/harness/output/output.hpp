// Writing a run's results: summary.json, metrics.csv, table.md, frame CSVs (see docs/).
// Everything is written into a command's staging folder (bench/harness/output/output_folder.hpp),
// which replaces the destination only when complete, so an interrupted run never leaves half a
// result.
#pragma once

#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "bench/harness/output/export.hpp"
#include "bench/harness/run/run.hpp"

namespace chainmail {

// write `text` to `path` through a temporary file and a rename (parents created)
void write_file_atomic(const std::string& path, const std::string& text);

nlohmann::json summary_json(const SceneRun& run);
// one sample's metrics as summary.json's "final" holds them (absent metrics left out)
nlohmann::json metrics_json(const Metrics& m);
// header of metrics.csv, and one row of it
std::string metrics_header();
std::string metrics_row(const std::string& backend, const Sample& sample);
std::string table_markdown(const SceneRun& run);
std::string frame_csv(const RingFrame& frame, const Weave& weave);
// the frame as the CSVs hold it: t (metrics.csv), positions and orientations (frame CSVs) rounded
// to the 9 significant digits they are written with, so that a frame drawn by the run and one
// read back from its files are the same numbers
void round_as_csv(RingFrame& frame);

struct OutputOptions {
  // draws images into <folder>/images from the runs' frame streams; empty = no rendering
  std::function<void(const SceneRun&, const std::string& images_folder)> render;
  // every backend's frames into <folder>/export/<backend>.glb|.npz, from the frame streams
  std::vector<ExportFormat> exports;
};

// summary.json, metrics.csv (from the rows streamed into <folder>/.streams), table.md, the
// images and the exports, into `folder` (a staging folder); the streams are removed after
void write_run_folder(const SceneRun& run, const std::string& folder, const OutputOptions& options);

}  // namespace chainmail

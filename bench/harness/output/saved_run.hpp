// A run folder read back: its resolved scene (summary.json), its backends in the order they ran
// (metrics.csv) and their saved frames (frames/<backend>/NNNNN.csv, with each sample's time from
// metrics.csv), so that they can be drawn or exported again without simulating.
#pragma once

#include <string>
#include <vector>

#include "bench/harness/output/frame_stream.hpp"
#include "core/scene.hpp"
#include "core/weave.hpp"

namespace chainmail {

struct SavedBackend {
  std::string name;
  double ms_per_step = -1.0;  // from summary.json; -1 when absent
  std::vector<double> times;  // (samples) s, metrics.csv's t column
  std::size_t frames = 0;     // frame CSVs, 00000.csv on without a gap
};

struct SavedRun {
  std::string path;
  Scene scene;
  Weave weave;
  std::vector<SavedBackend> backends;  // every backend of the run, in its order

  // frame k of a backend: its CSV's rings at the time of sample k
  FrameSequence frames(const SavedBackend& backend) const;
};

// reads summary.json and metrics.csv and counts the frame CSVs; throws UsageError naming the
// folder or the file and line when it is not a run folder chainmail could have written
SavedRun read_saved_run(const std::string& path);

// one frame CSV (ring,i,j,x,y,z,qw,qx,qy,qz; one row per ring in order); throws UsageError
// naming the file and line
void read_frame_csv(const std::string& path, int rings, RingFrame& frame);

}  // namespace chainmail

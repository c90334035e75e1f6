// The reference run drape_rms is measured against: which backend, where its frames come from
// while the other backends of a scene are measured, and its cache file.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "bench/harness/output/frame_stream.hpp"
#include "bench/harness/run/run.hpp"

namespace chainmail {

struct ReferenceSource {
  std::string backend;                // "" = no reference (drape_rms absent)
  std::string unbuilt;                // the reference named, when it is not built into this binary
  bool from_selected = false;         // one of the selected runs is the reference
  std::optional<FrameReader> reader;  // open once the reference frames exist
  std::string cache_path;             // "" without a cache folder
  std::string temporary;              // a stream file of its own, removed when the scene is done
  RingFrame frame;                    // the reference frame last read
  std::size_t index = static_cast<std::size_t>(-1);

  // drape_rms of a frame against the reference frame nearest in time (nullopt without one)
  std::optional<double> drape(const RingFrame& f);
  // the selected run that is the reference has finished: a stable one's frames become the
  // reference (and go into the cache); its stream is dropped unless the options keep streams
  void adopt(BackendRun& run, const RunOptions& options, int rings);
  // where drape_rms came from (summary.json, table.md)
  std::string note() const;
  void remove_temporary() const;
};

// the reference of a scene run: its cache file, else a selected run at the reference dt (moved
// to the front of `order`), else a run of its own, now
ReferenceSource prepare_reference(const Scene& scene, const Weave& weave, const RunOptions& options,
                                  std::vector<std::string>& order);

// one backend with its samples streamed into options.folder (scene_run.cpp); `is_reference`: its
// frames are the reference, kept in the stream file run.stream
BackendRun run_streamed(const Scene& scene, const Weave& weave, const std::string& name,
                        const RunOptions& options, ReferenceSource& reference, bool is_reference);

}  // namespace chainmail

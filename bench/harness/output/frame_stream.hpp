// Sampled frames on disk, appended while a run goes, read back one at a time.
// A stream is a 32-byte header (magic, ring count, record layout) followed by fixed-size records
// (t, positions, orientations). There is no count to trust: it follows from the file size, and a
// file whose size is not whole records of its header's layout is refused, never allocated for (the
// reference cache is such a file: a bad one is a miss).
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/frame.hpp"

namespace chainmail {

class FrameWriter {
 public:
  // opens (truncates) `path`; ok() is false when it cannot be written
  FrameWriter(const std::string& path, int rings);
  bool ok() const { return file_ != nullptr && !failed_; }
  void append(const RingFrame& frame);  // positions and orientations; velocities are not kept
  bool close();                         // flushes; false when anything failed

 private:
  struct Closer {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::unique_ptr<std::FILE, Closer> file_;
  int rings_ = 0;
  bool failed_ = false;
  std::vector<double> record_;
};

class FrameReader {
 public:
  // nullopt when the file is missing, unreadable, of another ring count, or not a whole stream
  static std::optional<FrameReader> open(const std::string& path, int rings);
  std::size_t count() const { return times_.size(); }
  double time(std::size_t k) const { return times_[k]; }
  // the record whose time is nearest to t (ties: the earlier one)
  std::size_t nearest(double t) const;
  // positions and orientations of record k (velocities zero); false on a read error
  bool read(std::size_t k, RingFrame& frame) const;

 private:
  struct Closer {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::shared_ptr<std::FILE> file_;
  int rings_ = 0;
  std::vector<double> times_;  // (count) s, read once at open
};

// copy a finished stream to `path` through a temporary name and a rename; false on failure
bool copy_stream(const std::string& from, const std::string& path);

// one backend's sampled frames in time order, read one at a time (from a stream, or from the
// frame CSVs of a saved run), so that what reads them needs memory for one frame only
struct FrameSequence {
  std::size_t count = 0;
  std::function<bool(std::size_t k, RingFrame& frame)> read;  // false on a read error
};
FrameSequence stream_sequence(FrameReader reader);

}  // namespace chainmail

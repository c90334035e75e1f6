// RingFrame: what every backend emits and all that metrics and the renderer ever see.
// The grid index of each ring is fixed topology and lives in Weave; a frame is the changing part.
#pragma once

#include <cstdint>

#include "core/types.hpp"

namespace chainmail {

struct RingFrame {
  double t = 0.0;            // s
  Positions position;        // (3, n) ring centres, m
  Orientations orientation;  // (4, n) unit quaternion (w, x, y, z), local ring frame -> world
  Positions velocity;        // (3, n) centre velocity, m/s

  int size() const { return static_cast<int>(position.cols()); }
  void resize(int n) {
    position.resize(3, n);
    orientation.resize(4, n);
    velocity.resize(3, n);
  }
  Quat quat(int ring) const {
    return Quat(orientation(0, ring), orientation(1, ring), orientation(2, ring),
                orientation(3, ring));
  }
  void set_quat(int ring, const Quat& q) { orientation.col(ring) << q.w(), q.x(), q.y(), q.z(); }
};

// 64-bit FNV-1a over the bit patterns of positions and orientations: same frame, same hash
std::uint64_t frame_hash(const RingFrame& frame);

}  // namespace chainmail

// The plausible model's per-ring passes ring by ring, plain scalar code: the oracle the lane
// kernels (core/plausible/plausible_rings_kernel.hpp, both builds) are compared with bit for bit.
#pragma once

#include <algorithm>

#include "core/plausible/plausible_rings.hpp"

namespace chainmail::oracle {

// predict_rings, ring by ring
inline RingMoves predict_rings(const RingArrays& r, const Vec3& fall, double h, int begin, int end,
                               const double* anchor = nullptr) {
  RingMoves moves;
  for (int i = begin; i < end; ++i) {
    for (int c = 0; c < 3; ++c) r.previous[3 * i + c] = r.position[3 * i + c];
    r.contact_push[i] = 0.0;
    if (r.inverse_mass[i] != 0.0) {  // else pinned
      for (int c = 0; c < 3; ++c) {
        r.velocity[3 * i + c] += fall[c];
        r.position[3 * i + c] += h * r.velocity[3 * i + c];
      }
    }
    if (!anchor) continue;
    moves.add(r.position[3 * i] - anchor[3 * i], r.position[3 * i + 1] - anchor[3 * i + 1],
              r.position[3 * i + 2] - anchor[3 * i + 2]);
  }
  return moves;
}

// update_ring_velocities, ring by ring
inline void update_ring_velocities(const RingArrays& r, double h, int begin, int end) {
  for (int i = begin; i < end; ++i) {
    const bool pinned = r.inverse_mass[i] == 0.0;
    for (int c = 0; c < 3; ++c) {
      r.velocity[3 * i + c] = pinned ? 0.0 : (r.position[3 * i + c] - r.previous[3 * i + c]) / h;
    }
  }
}

}  // namespace chainmail::oracle

// The prediction and velocity passes of core/plausible_rings.hpp: the moves' bookkeeping, and the
// passes' lane kernels (core/plausible_rings_kernel.hpp) chosen at run time.
#include "core/plausible_rings.hpp"

#include <algorithm>

#include "core/plausible_lanes.hpp"

namespace chainmail {

void RingMoves::add(double x, double y, double z) {
  farthest2 = std::max(farthest2, (x * x + y * y) + z * z);  // squaredNorm's order
  const double move[3] = {x, y, z};                          // m
  for (int c = 0; c < 3; ++c) {
    lo[c] = std::min(lo[c], move[c]);
    hi[c] = std::max(hi[c], move[c]);
  }
}

void RingMoves::join(const RingMoves& other) {
  farthest2 = std::max(farthest2, other.farthest2);
  for (int c = 0; c < 3; ++c) {
    lo[c] = std::min(lo[c], other.lo[c]);
    hi[c] = std::max(hi[c], other.hi[c]);
  }
}

RingMoves predict_rings(const RingArrays& rings, const Vec3& fall, double h, int begin, int end,
                        bool vector, const double* anchor) {
  return lane_kernels(vector).predict_rings(rings, fall, h, begin, end, anchor);
}

RingMoves update_velocities_and_predict(const RingArrays& rings, const Vec3& fall, double h,
                                        int begin, int end, bool vector, const double* anchor) {
  return lane_kernels(vector).update_velocities_and_predict(rings, fall, h, begin, end, anchor);
}

void update_ring_velocities(const RingArrays& rings, double h, int begin, int end, bool vector) {
  lane_kernels(vector).update_ring_velocities(rings, h, begin, end);
}

}  // namespace chainmail

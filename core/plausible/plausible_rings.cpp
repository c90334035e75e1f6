// The prediction and velocity passes of core/plausible/plausible_rings.hpp: the moves' bookkeeping,
// and the passes' lane kernels (core/plausible/plausible_rings_kernel.hpp) chosen at run time.
#include "core/plausible/plausible_rings.hpp"

#include <algorithm>

#include "core/plausible/plausible_lanes.hpp"

namespace chainmail {

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

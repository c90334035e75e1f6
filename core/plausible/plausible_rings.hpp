// The plausible model's two passes over every ring each substep, the prediction and the velocity
// update, four rings at a time in lanes (core/plausible/plausible_rings_kernel.hpp): AVX2 where the
// machine has it (core/plausible/plausible_blocks: vector_sweeps_available), else the portable
// lanes, the same bits. `vector` false asks for the portable lanes anyway: a hook for tests and
// benchmarks.
#pragma once

#include "core/plausible/ring_arrays.hpp"
#include "core/types.hpp"

namespace chainmail {

// rings [begin, end) under gravity alone: previous = position, contact_push = 0, and for a free
// ring velocity += fall, position += h velocity (pinned rings keep both). With an anchor (3 n),
// also the moves of the new positions from it (one pass less than measuring them after).
RingMoves predict_rings(const RingArrays& rings, const Vec3& fall, double h, int begin, int end,
                        bool vector = true, const double* anchor = nullptr);

// the velocity update of the substep before (update_ring_velocities over h) and then the
// prediction (predict_rings), in one pass: each ring's position is read once for both. The same
// arithmetic as the two passes one after the other, so the same bits
RingMoves update_velocities_and_predict(const RingArrays& rings, const Vec3& fall, double h,
                                        int begin, int end, bool vector = true,
                                        const double* anchor = nullptr);

// rings [begin, end): velocity = (position - previous) / h for a free ring, 0 for a pinned one
// (collider friction is the caller's, after)
void update_ring_velocities(const RingArrays& rings, double h, int begin, int end,
                            bool vector = true);

}  // namespace chainmail

// The plausible model's lane kernels: the per-ring passes (core/plausible/plausible_rings.hpp) and
// the sweeps' blocks (core/plausible/plausible_blocks.hpp), written once over a lane type
// (core/plausible/lanes.hpp) in core/plausible/plausible_rings_kernel.hpp and
// core/plausible/plausible_blocks_kernel.hpp, and compiled twice: over the portable lanes
// (plausible_lanes_scalar.cpp) and over AVX2 (plausible_lanes_avx2.cpp). Both give the same bits;
// lane_kernels picks one at run time.
#pragma once

#include "core/plausible/constraints.hpp"
#include "core/plausible/lanes.hpp"
#include "core/plausible/pin_attachments.hpp"
#include "core/plausible/ring_arrays.hpp"
#include "core/plausible/sweep_records.hpp"
#include "core/types.hpp"

namespace chainmail {

// one build of the kernels (the arguments as in the functions of the same names)
struct LaneKernels {
  RingMoves (*predict_rings)(const RingArrays& rings, const Vec3& fall, double h, int begin,
                             int end, const double* anchor);
  RingMoves (*update_velocities_and_predict)(const RingArrays& rings, const Vec3& fall, double h,
                                             int begin, int end, const double* anchor);
  void (*update_ring_velocities)(const RingArrays& rings, double h, int begin, int end);
  double (*sweep_pair_blocks)(double* x, const double* w, const EdgeConstraint* pairs,
                              const PairBlock* blocks, int count);
  double (*sweep_attachment_blocks)(double* x, const PinAttachment* list, const double* reach,
                                    const AttachmentBlock* blocks, int count);
};

extern const LaneKernels kScalarLaneKernels;
#if defined(CHAINMAIL_AVX2_SWEEPS)
extern const LaneKernels kAvx2LaneKernels;  // call only where vector_sweeps_available()
#endif

// the AVX2 build where `vector` and the machine has AVX2, else the portable one. `vector` is a
// hook for tests and benchmarks (PlausibleSim::set_vector_sweeps): the two give the same bits
const LaneKernels& lane_kernels(bool vector);

}  // namespace chainmail

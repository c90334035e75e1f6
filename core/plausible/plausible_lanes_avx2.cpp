// The plausible model's lane kernels (core/plausible/plausible_lanes.hpp) over AVX2 lanes. This
// file builds without -mavx2: each kernel function carries the AVX2 target itself, so nothing else
// compiled here (inline functions the linker might pick for other callers) uses AVX2 instructions,
// and the kernels run only where lane_kernels finds the machine has them.
#include "core/plausible/lanes.hpp"
#include "core/plausible/plausible_lanes.hpp"

#if defined(CHAINMAIL_AVX2_SWEEPS)
#include "core/plausible/lanes_avx2.hpp"

#define CHAINMAIL_LANES_NAMESPACE avx2_lanes
#define CHAINMAIL_LANES_FN __attribute__((target("avx2")))
#define CHAINMAIL_LANES_INLINE CHAINMAIL_AVX2_INLINE

namespace chainmail::avx2_lanes {
using L = Avx2Lanes;
using M = L::Mask;
}  // namespace chainmail::avx2_lanes

#include "core/plausible/plausible_blocks_kernel.hpp"
#include "core/plausible/plausible_rings_kernel.hpp"

namespace chainmail {

const LaneKernels kAvx2LaneKernels = {
    &avx2_lanes::predict_rings, &avx2_lanes::update_velocities_and_predict,
    &avx2_lanes::update_ring_velocities, &avx2_lanes::sweep_pair_blocks,
    &avx2_lanes::sweep_attachment_blocks};

}  // namespace chainmail
#endif

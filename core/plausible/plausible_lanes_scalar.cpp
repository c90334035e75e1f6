// The plausible model's lane kernels (core/plausible/plausible_lanes.hpp) over the portable lanes:
// the build every machine runs, and the one tests compare the AVX2 build with.
#include "core/plausible/lanes.hpp"
#include "core/plausible/plausible_lanes.hpp"

#define CHAINMAIL_LANES_NAMESPACE scalar_lanes
#define CHAINMAIL_LANES_FN
#define CHAINMAIL_LANES_INLINE inline

namespace chainmail::scalar_lanes {
using L = ScalarLanes;
using M = L::Mask;
}  // namespace chainmail::scalar_lanes

#include "core/plausible/plausible_blocks_kernel.hpp"
#include "core/plausible/plausible_rings_kernel.hpp"

namespace chainmail {

const LaneKernels kScalarLaneKernels = {
    &scalar_lanes::predict_rings, &scalar_lanes::update_velocities_and_predict,
    &scalar_lanes::update_ring_velocities, &scalar_lanes::sweep_pair_blocks,
    &scalar_lanes::sweep_attachment_blocks};

}  // namespace chainmail

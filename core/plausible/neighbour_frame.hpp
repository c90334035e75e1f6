// A ring's frame from its four links: along its (i) neighbours, across, and the sheet's normal.
// The frame turns with the sheet around the ring but not with the ring's own swivel, so a
// direction fixed in it (a ring's rest lean) follows the sheet as it folds and drapes without
// feeding the pushes it steers back into itself.
#pragma once

#include <Eigen/Core>

#include "core/types.hpp"
#include "core/weave.hpp"

namespace chainmail {

// ring r's frame in positions x (3, n), m: columns unit along (i - 1, j) -> (i + 1, j), across in
// the sheet, and the sheet normal (the first two crossed); a missing neighbour's place is taken
// by r. False where the neighbours span no plane (a ring with fewer than one on each axis)
bool neighbour_frame(const Weave& weave, const Positions& x, int r, Eigen::Matrix3d& frame);

// each ring's rest axis (its rest orientation's y) in its rest neighbour frame, (3, n); 0 where
// the ring has no frame
Positions rest_axes_in_frame(const Weave& weave);

// ring r's axis now: its rest axis turned with its neighbour frame in x; 0 without a frame
Vec3 axis_in_frame(const Weave& weave, const Positions& rest_in_frame, const Positions& x, int r);

}  // namespace chainmail

// Long-range attachments (Kim, Chentanez and Müller 2012, "Long Range Attachments"): a ring k
// links from a pin is never farther from it than k longest links, whatever the weave between them
// does, so the distance to the pin is a valid upper bound that one projection per ring enforces.
// Gauss-Seidel sweeps move a stretch along a hanging sheet one row per sweep; the attachments
// remove the sheet-wide part in one pass, so the sweeps a large sheet needs do not grow with it.
//
// Each ring is attached to the pins at the fewest links from it, and of those only to the two
// farthest apart along the sheet's rows: a ring below a pinned edge is held by the pins at the
// ends of the edge's stretch it can reach, whose two spheres bound its drop as tightly as the
// zigzag of 4-in-1 links does while the edge holds the rows' width.
#pragma once

#include <array>
#include <vector>

#include "core/plausible/pin_paths.hpp"
#include "core/types.hpp"
#include "core/weave.hpp"

namespace chainmail {

struct PinAttachment {
  int ring;
  int pin;
  double max_distance;  // m, links from the pin * the longest link
};

// two lists, each with at most one attachment per ring (so each list's projections touch
// disjoint rings and may run in parallel); rings no pin reaches, and pins, have none
using PinAttachments = std::array<std::vector<PinAttachment>, 2>;

PinAttachments pin_attachments(const Weave& weave, const PinPaths& paths,
                               const std::vector<int>& pinned, double longest_link);

}  // namespace chainmail

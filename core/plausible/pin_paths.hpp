// Orientation information propagated from the fixed points through the weave (paper §6): the
// rings in breadth-first order from the pins, and for each ring the direction in which the weave
// holds it up: the mean vector to the pins it hangs from, summed along its shortest paths. A sheet
// hung from its top edge is held straight up; one hung from its two top corners is held toward
// the nearer corner, so its rings swivel along the diagonals a corner-hung sheet forms.
#pragma once

#include <array>
#include <vector>

#include "core/types.hpp"
#include "core/weave.hpp"

namespace chainmail {

struct PinPaths {
  std::vector<int> order;                   // (k) rings reachable from a pin, by depth; no pins
  std::vector<std::array<int, 4>> parents;  // (k) neighbours one link nearer a pin, -1 padded
  std::vector<int> depth;                   // (n) links from the nearest pin, -1 unreachable
};

// breadth-first from the pinned rings over the weave's links
PinPaths pin_paths(const Weave& weave, const std::vector<int>& pinned);

// pull (3, n), m: for each ring in order, the mean over its parents of (parent - ring) plus the
// parent's own pull; pins and unreachable rings get 0. Since the steps of a path add up, a ring's
// pull is the mean of the vectors from it to the pins its shortest paths end at.
void pull_toward_pins(const PinPaths& paths, const Positions& position, Positions& pull);

}  // namespace chainmail

// Greedy colouring of pair constraints: within one colour no two pairs share a ring, so a colour's
// projections are independent and may run in any order or in parallel with the same result,
// while the sweep stays Gauss-Seidel from colour to colour.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace chainmail {

// colour c holds items [start[c], start[c + 1]); the last colour is `serial` when some pairs
// found no free colour among the 64 (they may share rings: solved in order, on one thread)
struct Colouring {
  std::vector<int> start = {0};  // (colours + 1)
  bool serial_tail = false;
  int colours() const { return static_cast<int>(start.size()) - 1; }
};

// reorders `pairs` (anything with int members a, b) by greedy colour, stably (the first pairs
// keep the lowest colours), and returns the colours' ranges
template <class Pair>
Colouring colour_pairs(std::vector<Pair>& pairs, int ring_count) {
  constexpr int kColours = 64;
  std::vector<std::uint64_t> used(ring_count, 0);     // (n) bit c set: ring has a pair of colour c
  std::vector<std::uint8_t> colour_of(pairs.size());  // (pairs) colour of each pair
  std::vector<int> start(kColours + 1, 0);            // (colours + 1) pairs before each colour
  bool overflow = false;
  for (size_t k = 0; k < pairs.size(); ++k) {
    const Pair& pair = pairs[k];
    const std::uint64_t taken = used[pair.a] | used[pair.b];
    int colour = 0;
    while (colour < kColours - 1 && (taken >> colour & 1u)) ++colour;
    if (colour == kColours - 1) overflow = true;
    used[pair.a] |= std::uint64_t{1} << colour;
    used[pair.b] |= std::uint64_t{1} << colour;
    colour_of[k] = static_cast<std::uint8_t>(colour);
    ++start[colour + 1];
  }
  // counting sort by colour: stable, linear in the pairs (a sheet recolours every rebuild)
  for (int c = 0; c < kColours; ++c) start[c + 1] += start[c];
  std::vector<Pair> sorted(pairs.size());
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (size_t k = 0; k < pairs.size(); ++k) sorted[fill[colour_of[k]]++] = pairs[k];
  pairs.swap(sorted);
  Colouring colouring;
  for (int c = 0; c < kColours; ++c) {
    if (start[c + 1] > start[c]) colouring.start.push_back(start[c + 1]);
  }
  colouring.serial_tail = overflow;
  return colouring;
}

}  // namespace chainmail

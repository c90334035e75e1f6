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
  std::vector<std::uint64_t> used(ring_count, 0);  // (n) bit c set: ring has a pair of colour c
  std::vector<std::pair<int, Pair>> coloured;
  coloured.reserve(pairs.size());
  bool overflow = false;
  for (const Pair& pair : pairs) {
    const std::uint64_t taken = used[pair.a] | used[pair.b];
    int colour = 0;
    while (colour < kColours - 1 && (taken >> colour & 1u)) ++colour;
    if (colour == kColours - 1) overflow = true;
    used[pair.a] |= std::uint64_t{1} << colour;
    used[pair.b] |= std::uint64_t{1} << colour;
    coloured.push_back({colour, pair});
  }
  std::stable_sort(coloured.begin(), coloured.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  Colouring colouring;
  for (size_t k = 0; k < coloured.size(); ++k) {
    pairs[k] = coloured[k].second;
    if (k + 1 == coloured.size() || coloured[k + 1].first != coloured[k].first) {
      colouring.start.push_back(static_cast<int>(k + 1));
    }
  }
  colouring.serial_tail = overflow;
  return colouring;
}

}  // namespace chainmail

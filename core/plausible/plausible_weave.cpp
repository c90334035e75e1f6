// The plausible model's compression limits from the weave's geometry (core/plausible/weave_limits):
// the closest approach of linked neighbours, and the distance bounds of rings that share two
// neighbours, solved in the same sweeps as the edges; and the weave's grid packed for the contact
// list's pair walk (GridKeys).
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/plausible/constraints.hpp"
#include "core/plausible/neighbour_frame.hpp"
#include "core/plausible/plausible.hpp"
#include "core/plausible/weave_limits.hpp"

namespace chainmail {

double PlausibleSim::build_compression_limits() {
  model_.diagonals.clear();
  model_.row_pairs.clear();
  model_.rest_axes.resize(3, 0);
  const double paper = model_.ring.min_link_distance();  // the wire thickness
  if (!model_.settings.compression_limits || model_.weave.type != WeaveType::four_in_one)
    return paper;
  const WeaveLimits limits = four_in_one_limits(model_.ring, model_.extended_swivel);
  // with row_slip, rings side by side in a row are also listed on their own (slide_rows)
  const bool slide = model_.settings.row_slip > 0.0;
  const auto& grid = model_.weave.grid;
  for (const DiagonalPair& pair : diagonal_pairs(model_.weave, limits)) {
    const bool row = grid[pair.b][0] - grid[pair.a][0] == grid[pair.b][1] - grid[pair.a][1];
    if (slide && row) model_.row_pairs.push_back({pair.a, pair.b, pair.min, pair.max});
    model_.diagonals.push_back({pair.a, pair.b, pair.min, pair.max});
  }
  if (slide) {
    // by ring: the look for pairs pushed together streams through the positions once
    std::sort(model_.row_pairs.begin(), model_.row_pairs.end(),
              [](const EdgeConstraint& x, const EdgeConstraint& y) { return x.a < y.a; });
    model_.rest_axes = rest_axes_in_frame(model_.weave);
  }
  // rings of adjacent rows a row and a half apart meet when a row is pushed together
  const size_t first_knight = model_.diagonals.size();
  for (const DiagonalPair& pair : knight_pairs(model_.weave, limits)) {
    model_.diagonals.push_back({pair.a, pair.b, pair.min, pair.max});
  }
  // the sweeps solve four pairs at once where a colour runs through consecutive rings
  // (core/plausible/plausible_blocks): listed by ring offset, then ring, these pairs colour into
  // such runs (the links and the pairs above, listed row by row, already do)
  std::stable_sort(model_.diagonals.begin() + static_cast<std::ptrdiff_t>(first_knight),
                   model_.diagonals.end(), [](const EdgeConstraint& x, const EdgeConstraint& y) {
                     const int dx = x.b - x.a, dy = y.b - y.a;
                     return dx != dy ? dx < dy : std::min(x.a, x.b) < std::min(y.a, y.b);
                   });
  return std::max(paper, limits.link);
}

GridKeys grid_keys(const Weave& weave, bool diagonals) {
  const int n = weave.size();
  GridKeys grid;
  grid.diagonals = diagonals;
  if (n == 0) return grid;
  int low[2] = {weave.grid[0][0], weave.grid[0][1]}, high[2] = {low[0], low[1]};
  for (const std::array<int, 2>& cell : weave.grid) {
    for (int k = 0; k < 2; ++k)
      low[k] = std::min(low[k], cell[k]), high[k] = std::max(high[k], cell[k]);
  }
  // a spare row and column of bits: a neighbour's cell one past the corner stays distinct
  const auto bits = [](long long span) {
    return static_cast<int>(std::bit_width(static_cast<unsigned long long>(span + 1)));
  };
  grid.column_bits = bits(static_cast<long long>(high[1]) - low[1]);
  if (grid.column_bits + bits(static_cast<long long>(high[0]) - low[0]) > 32) {
    throw std::invalid_argument("plausible: the weave's grid spans more cells than 32 bits number");
  }
  auto pack = [&](long long i, long long j) {
    return static_cast<std::uint32_t>(i - low[0]) << grid.column_bits |
           static_cast<std::uint32_t>(j - low[1]);
  };
  auto inside = [&](long long i, long long j) {
    return i >= low[0] && i <= high[0] && j >= low[1] && j <= high[1];
  };
  grid.key.resize(n);
  for (int r = 0; r < n; ++r) grid.key[r] = pack(weave.grid[r][0], weave.grid[r][1]);
  std::vector<std::uint32_t> sorted = grid.key;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
    throw std::invalid_argument("plausible: two rings of the weave share a grid cell");
  }
  // each listed neighbour where the grid puts it, and no ring where the list has none
  constexpr int kStep[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};  // the lists' order
  for (int r = 0; r < n; ++r) {
    for (int k = 0; k < 4; ++k) {
      const long long i = weave.grid[r][0] + kStep[k][0], j = weave.grid[r][1] + kStep[k][1];
      const int listed = weave.neighbours[r][k];
      const bool agrees =
          listed >= 0
              ? weave.grid[listed][0] == i && weave.grid[listed][1] == j
              : !inside(i, j) || !std::binary_search(sorted.begin(), sorted.end(), pack(i, j));
      if (!agrees) {
        throw std::invalid_argument("plausible: ring " + std::to_string(r) +
                                    "'s neighbours are not its grid-adjacent rings");
      }
    }
  }
  return grid;
}

}  // namespace chainmail

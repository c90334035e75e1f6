// The plausible model's compression limits from the weave's geometry (core/weave_limits): the
// closest approach of linked neighbours, and the distance bounds of rings that share two
// neighbours, solved in the same sweeps as the edges; and the weave's grid packed for the contact
// list's pair walk.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "core/plausible/constraints.hpp"
#include "core/plausible/plausible.hpp"
#include "core/plausible/weave_limits.hpp"

namespace chainmail {

double PlausibleSim::build_compression_limits() {
  model_.diagonals.clear();
  const double paper = model_.ring.min_link_distance();  // the wire thickness
  if (!model_.settings.compression_limits || weave_.type != WeaveType::four_in_one) return paper;
  const WeaveLimits limits = four_in_one_limits(model_.ring, model_.extended_swivel);
  for (const DiagonalPair& pair : diagonal_pairs(weave_, limits)) {
    model_.diagonals.push_back({pair.a, pair.b, pair.min, pair.max});
  }
  // rings of adjacent rows a row and a half apart meet when a row is pushed together
  const size_t first_knight = model_.diagonals.size();
  for (const DiagonalPair& pair : knight_pairs(weave_, limits)) {
    model_.diagonals.push_back({pair.a, pair.b, pair.min, pair.max});
  }
  // the sweeps solve four pairs at once where a colour runs through consecutive rings
  // (core/plausible_blocks): listed by ring offset, then ring, these pairs colour into such runs
  // (the links and the pairs above, listed row by row, already do)
  std::stable_sort(model_.diagonals.begin() + static_cast<std::ptrdiff_t>(first_knight),
                   model_.diagonals.end(), [](const EdgeConstraint& x, const EdgeConstraint& y) {
                     const int dx = x.b - x.a, dy = y.b - y.a;
                     return dx != dy ? dx < dy : std::min(x.a, x.b) < std::min(y.a, y.b);
                   });
  return std::max(paper, limits.link);
}

void PlausibleSim::build_grid_keys() {
  grid_key_.clear();
  const int n = weave_.size();
  auto pack = [](int i, int j) {
    return static_cast<std::uint32_t>(i) << 16 | static_cast<std::uint32_t>(j);
  };
  auto fits = [](int i, int j) { return i >= 0 && j >= 0 && i <= 0xffff && j <= 0xffff; };
  std::vector<std::uint32_t> keys(n);
  for (int r = 0; r < n; ++r) {
    if (!fits(weave_.grid[r][0], weave_.grid[r][1])) return;
    keys[r] = pack(weave_.grid[r][0], weave_.grid[r][1]);
  }
  std::vector<std::uint32_t> sorted = keys;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return;  // a shared cell
  // each listed neighbour where the grid puts it, and no ring where the list has none
  constexpr int kStep[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};  // the lists' order
  for (int r = 0; r < n; ++r) {
    for (int k = 0; k < 4; ++k) {
      const int i = weave_.grid[r][0] + kStep[k][0], j = weave_.grid[r][1] + kStep[k][1];
      const int listed = weave_.neighbours[r][k];
      if (listed >= 0) {
        if (weave_.grid[listed][0] != i || weave_.grid[listed][1] != j) return;
      } else if (fits(i, j) && std::binary_search(sorted.begin(), sorted.end(), pack(i, j))) {
        return;
      }
    }
  }
  grid_key_ = std::move(keys);
}

}  // namespace chainmail

// The plausible model's compression limits from the weave's geometry (core/weave_limits): the
// closest approach of linked neighbours, and the distance bounds of rings that share two
// neighbours, solved in the same sweeps as the edges.
#include <algorithm>
#include <cstdlib>

#include "core/constraints.hpp"
#include "core/plausible.hpp"
#include "core/weave_limits.hpp"

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
  // past the Newton steps' size the sweeps solve four pairs at once where a colour runs through
  // consecutive rings (core/plausible_blocks): listed by ring offset, then ring, these pairs
  // colour into such runs (the links and the pairs above, listed row by row, already do)
  if (static_cast<int>(weave_.size()) > model_.settings.newton_max_rings) {
    std::stable_sort(model_.diagonals.begin() + static_cast<std::ptrdiff_t>(first_knight),
                     model_.diagonals.end(), [](const EdgeConstraint& x, const EdgeConstraint& y) {
                       const int dx = x.b - x.a, dy = y.b - y.a;
                       return dx != dy ? dx < dy : std::min(x.a, x.b) < std::min(y.a, y.b);
                     });
  }
  return std::max(paper, limits.link);
}

}  // namespace chainmail

#include "core/plausible/pin_attachments.hpp"

namespace chainmail {

PinAttachments pin_attachments(const Weave& weave, const PinPaths& paths,
                               const std::vector<int>& pinned, double longest_link) {
  const int n = weave.size();
  // each ring's nearest pins (by links), as the two extremes along the row axis: every shortest
  // path passes through a parent, so a ring's nearest pins are the union of its parents'
  std::vector<int> low(n, -1), high(n, -1);  // (n) pin rings
  auto along = [&](int ring) { return weave.row_axis.dot(weave.rest_position.col(ring)); };
  // ties keep the smaller ring index, so the choice does not depend on the parents' order
  auto better = [&](int candidate, int current, bool below) {
    if (current < 0) return true;
    const double c = along(candidate), o = along(current);
    return below ? (c < o || (c == o && candidate < current))
                 : (c > o || (c == o && candidate < current));
  };
  for (int pin : pinned) low[pin] = high[pin] = pin;
  for (size_t k = 0; k < paths.order.size(); ++k) {
    const int ring = paths.order[k];
    for (int parent : paths.parents[k]) {
      if (parent < 0) break;
      if (better(low[parent], low[ring], true)) low[ring] = low[parent];
      if (better(high[parent], high[ring], false)) high[ring] = high[parent];
    }
  }
  PinAttachments lists;
  for (int ring : paths.order) {
    const double reach = paths.depth[ring] * longest_link;  // m
    lists[0].push_back({ring, low[ring], reach});
    if (high[ring] != low[ring]) lists[1].push_back({ring, high[ring], reach});
  }
  return lists;
}

}  // namespace chainmail

#include "core/plausible/pin_paths.hpp"

namespace chainmail {

PinPaths pin_paths(const Weave& weave, const std::vector<int>& pinned) {
  const int n = weave.size();
  PinPaths paths;
  paths.depth.assign(n, -1);
  std::vector<int> queue;
  for (int ring : pinned) {
    if (paths.depth[ring] == 0) continue;
    paths.depth[ring] = 0;
    queue.push_back(ring);
  }
  for (size_t head = 0; head < queue.size(); ++head) {
    const int ring = queue[head];
    for (int other : weave.neighbours[ring]) {
      if (other < 0 || paths.depth[other] >= 0) continue;
      paths.depth[other] = paths.depth[ring] + 1;
      queue.push_back(other);
    }
  }
  // the queue is in depth order: every ring after the pins, with its parents
  for (int ring : queue) {
    if (paths.depth[ring] == 0) continue;
    std::array<int, 4> parents = {-1, -1, -1, -1};
    int count = 0;
    for (int other : weave.neighbours[ring]) {
      if (other >= 0 && paths.depth[other] == paths.depth[ring] - 1) parents[count++] = other;
    }
    paths.order.push_back(ring);
    paths.parents.push_back(parents);
  }
  return paths;
}

void pull_toward_pins(const PinPaths& paths, const Positions& position, Positions& pull) {
  pull.setZero(3, position.cols());
  for (size_t k = 0; k < paths.order.size(); ++k) {
    const int ring = paths.order[k];
    Vec3 sum = Vec3::Zero();
    int count = 0;
    for (int parent : paths.parents[k]) {
      if (parent < 0) break;
      sum += position.col(parent) - position.col(ring) + pull.col(parent);
      ++count;
    }
    pull.col(ring) = sum / count;  // count >= 1: a ring at depth d has a parent at d - 1
  }
}

}  // namespace chainmail

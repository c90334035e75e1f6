// Threads for the models' data-parallel loops. Every parallel loop in core runs over items that
// touch disjoint state (rings, or constraints of one colour) with a static schedule, and reduces
// only with max: its result is bitwise the same for any thread count.
#pragma once

#include <algorithm>
#include <thread>

#if defined(CHAINMAIL_HAS_OPENMP)
#include <omp.h>
#endif

namespace chainmail {

// hardware threads of this machine (1 when unknown)
inline int hardware_threads() {
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

// whether this build can run loops on more than one thread
inline bool parallel_loops_available() {
#if defined(CHAINMAIL_HAS_OPENMP)
  return true;
#else
  return false;
#endif
}

// threads a loop of `count` items runs on: below `grain` items per thread the hand-over costs
// more than it saves
inline int loop_threads(int threads, int count, int grain = 512) {
  if (!parallel_loops_available()) return 1;
  return std::clamp(count / std::max(1, grain), 1, std::max(1, threads));
}

}  // namespace chainmail

// Threads for the models' data-parallel loops. Every parallel loop in core runs over items that
// touch disjoint state (rings, or constraints of one colour) with a static schedule, and reduces
// only with max: its result is bitwise the same for any thread count.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <new>
#include <thread>
#include <vector>

#if defined(CHAINMAIL_HAS_OPENMP)
#include <omp.h>
#endif

namespace chainmail {

// hardware threads of this machine (1 when unknown)
inline int hardware_threads() {
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

// threads a step should use, called once before each step (a model's loops then use that many for
// the whole step): `requested`, or fewer while other processes keep cores busy, so that no thread
// of a team waits for a core at every barrier (on a machine whose cores are all taken, two
// threads can be many times slower than one). The result of a step does not depend on it. The
// environment variable CHAINMAIL_ADAPT_THREADS=0 turns this off (always `requested`).
int threads_for_step(int requested);

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

// body(i) for i in [begin, end), on `team` threads with a static schedule. A team of one runs the
// loop here: entering the OpenMP runtime wakes its pool of threads even for a team of one, a cost
// a small sheet's step would pay at every loop
template <class Body>
void parallel_for(int begin, int end, int team, Body&& body) {
#if defined(CHAINMAIL_HAS_OPENMP)
  if (team > 1) {
#pragma omp parallel for schedule(static) num_threads(team)
    for (int i = begin; i < end; ++i) body(i);
    return;
  }
#endif
  for (int i = begin; i < end; ++i) body(i);
}

// the largest of `worst` and every body(i), i in [begin, end), as parallel_for runs them
template <class Body>
double parallel_max(int begin, int end, int team, double worst, Body&& body) {
#if defined(CHAINMAIL_HAS_OPENMP)
  if (team > 1) {
#pragma omp parallel for schedule(static) num_threads(team) reduction(max : worst)
    for (int i = begin; i < end; ++i) worst = std::max(worst, body(i));
    return worst;
  }
#endif
  for (int i = begin; i < end; ++i) worst = std::max(worst, body(i));
  return worst;
}

// bytes in a cache line (x86-64 and most ARM cores): data two threads write at once is aligned to
// it (alignas(kCacheLine)) so that each writes lines of its own
inline constexpr std::size_t kCacheLine = 64;

// one T for each of N threads (or parts of the work), each on cache lines of its own: threads
// that push into neighbouring vectors side by side would otherwise hand the line holding their
// ends back and forth at every push
template <class T, std::size_t N>
class PerThread {
 public:
  T& operator[](std::size_t k) { return slots_[k].value; }
  const T& operator[](std::size_t k) const { return slots_[k].value; }
  static constexpr std::size_t size() { return N; }

 private:
  struct alignas(kCacheLine) Slot {
    T value{};
  };
  std::array<Slot, N> slots_;
};

// an allocator whose blocks start on a cache line (kCacheLine): where two threads write the items
// on either side of a boundary that falls on a line's edge, they then write lines of their own
template <class T>
struct CacheLineAllocator {
  using value_type = T;
  static constexpr std::align_val_t kAlignment{kCacheLine};
  CacheLineAllocator() = default;
  template <class U>
  CacheLineAllocator(const CacheLineAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), kAlignment)); }
  void deallocate(T* p, std::size_t) noexcept { ::operator delete(p, kAlignment); }
  template <class U>
  bool operator==(const CacheLineAllocator<U>&) const noexcept {
    return true;
  }
};
template <class T>
using CacheLineVector = std::vector<T, CacheLineAllocator<T>>;

}  // namespace chainmail

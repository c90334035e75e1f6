// core/parallel.hpp: per-thread slots and cache-line-aligned arrays, the layout that keeps two
// threads writing side by side off each other's cache lines; the threads a step takes on a busy
// machine; the loops that run a team of one outside the OpenMP runtime.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "core/parallel.hpp"
#include "core/types.hpp"

namespace chainmail {
namespace {

constexpr std::uintptr_t kLine = kCacheLine;

TEST(CacheLineVector, EveryBlockStartsOnACacheLine) {
  // sizes that malloc would otherwise place on 16-byte boundaries
  for (int n : {1, 3, 17, 256, 1000}) {
    CacheLineVector<Vec3> positions(n, Vec3::Zero());
    CacheLineVector<char> flags(n, 0);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(positions.data()) % kLine, 0u) << n;
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(flags.data()) % kLine, 0u) << n;
    positions.resize(2 * n + 1);  // a reallocation keeps the alignment, and the values
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(positions.data()) % kLine, 0u) << n;
    EXPECT_EQ(positions[n - 1], Vec3::Zero());
  }
}

TEST(PerThread, SlotsSitOnCacheLinesOfTheirOwn) {
  PerThread<long long, 3> counts;
  for (std::size_t k = 0; k < counts.size(); ++k) counts[k] = static_cast<long long>(k) + 1;
  for (std::size_t k = 0; k + 1 < counts.size(); ++k) {
    const auto here = reinterpret_cast<std::uintptr_t>(&counts[k]);
    const auto next = reinterpret_cast<std::uintptr_t>(&counts[k + 1]);
    EXPECT_GE(next - here, kLine);
    EXPECT_NE(here / kLine, next / kLine);
    EXPECT_EQ(counts[k], static_cast<long long>(k) + 1);
  }
}

TEST(ParallelFor, EveryIndexOnceOnAnyTeam) {
  for (int team : {1, 2, 3}) {
    std::vector<int> visits(1000, 0);
    parallel_for(7, 1000, team, [&](int i) { ++visits[i]; });
    for (int i = 0; i < 1000; ++i) EXPECT_EQ(visits[i], i < 7 ? 0 : 1) << team << " " << i;
  }
  int calls = 0;
  parallel_for(5, 5, 2, [&](int) { ++calls; });  // an empty range runs nothing
  EXPECT_EQ(calls, 0);
}

TEST(ParallelFor, ATeamOfOneRunsOutsideTheRuntime) {
#if defined(CHAINMAIL_HAS_OPENMP)
  // the team of one runs here, in order; a larger team runs in a parallel region
  std::vector<int> order;
  bool inside = true;
  parallel_for(0, 50, 1, [&](int i) {
    order.push_back(i);
    inside = inside && omp_in_parallel();
  });
  EXPECT_FALSE(inside);
  for (int i = 0; i < 50; ++i) EXPECT_EQ(order[i], i);
  std::vector<char> in_region(50, 0);
  parallel_for(0, 50, 2, [&](int i) { in_region[i] = omp_in_parallel() ? 1 : 0; });
  for (int i = 0; i < 50; ++i) EXPECT_EQ(in_region[i], 1) << i;
#else
  GTEST_SKIP() << "built without OpenMP: every loop runs on one thread";
#endif
}

TEST(ParallelMax, TheLargestOfTheStartAndEveryItemOnAnyTeam) {
  std::vector<double> values(777);
  for (int i = 0; i < 777; ++i) values[i] = static_cast<double>((i * 37) % 501);
  for (int team : {1, 2, 4}) {
    EXPECT_EQ(parallel_max(0, 777, team, 0.0, [&](int i) { return values[i]; }), 500.0) << team;
    // the start wins where every item is below it; an empty range returns it
    EXPECT_EQ(parallel_max(0, 777, team, 600.0, [&](int i) { return values[i]; }), 600.0) << team;
    EXPECT_EQ(parallel_max(10, 10, team, 3.5, [&](int i) { return values[i]; }), 3.5) << team;
    // one item: its own value, (13 * 37) % 501
    EXPECT_EQ(parallel_max(13, 14, team, 0.0, [&](int i) { return values[i]; }), 481.0) << team;
  }
}

TEST(ThreadsForStep, OneThreadStaysOneAndNoneIsEverAdded) {
  EXPECT_EQ(threads_for_step(1), 1);
  EXPECT_EQ(threads_for_step(0), 1);
  for (int k = 0; k < 5; ++k) {
    const int threads = threads_for_step(8);
    EXPECT_GE(threads, 1);
    EXPECT_LE(threads, 8);
  }
}

TEST(ThreadsForStep, FewerWhileOtherProcessesHoldEveryCore) {
  const int cores = hardware_threads();
  if (cores < 2) GTEST_SKIP() << "one core: nothing to share";
  if (const char* adapt = std::getenv("CHAINMAIL_ADAPT_THREADS");
      adapt && adapt == std::string("0"))
    GTEST_SKIP() << "CHAINMAIL_ADAPT_THREADS=0";
  // one spinning process per core (other processes: this process's own threads do not count)
  std::vector<pid_t> children;
  for (int k = 0; k < cores; ++k) {
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(3);
      while (std::chrono::steady_clock::now() < end) {
      }
      _exit(0);
    }
    children.push_back(child);
  }
  // the windows are a tenth of a second: after half a second they all saw the load
  int threads = cores;
  for (int k = 0; k < 10; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(60));
    threads = threads_for_step(cores);
  }
  for (const pid_t child : children) {
    kill(child, SIGKILL);
    waitpid(child, nullptr, 0);
  }
  EXPECT_LT(threads, cores);
}

}  // namespace
}  // namespace chainmail

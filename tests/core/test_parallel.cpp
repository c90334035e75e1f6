// core/parallel.hpp: per-thread slots and cache-line-aligned arrays, the layout that keeps two
// threads writing side by side off each other's cache lines.
#include <gtest/gtest.h>

#include <cstdint>

#include "core/parallel.hpp"
#include "core/types.hpp"

namespace chainmail {
namespace {

constexpr std::uintptr_t kLine = 64;

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

}  // namespace
}  // namespace chainmail

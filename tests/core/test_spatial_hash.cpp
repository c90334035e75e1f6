#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "core/spatial_hash.hpp"

namespace chainmail {
namespace {

using PairSet = std::set<std::pair<int, int>>;

PairSet brute_force_pairs(const Positions& x, double radius) {
  PairSet pairs;
  for (int i = 0; i < x.cols(); ++i) {
    for (int j = i + 1; j < x.cols(); ++j) {
      if ((x.col(i) - x.col(j)).squaredNorm() < radius * radius) pairs.insert({i, j});
    }
  }
  return pairs;
}

// every pair once, i < j, and exactly the brute-force set
void expect_same_pairs(const SpatialHash& hash, const Positions& x, double radius) {
  PairSet found;
  int visits = 0;
  hash.for_each_pair(x, radius, [&](int i, int j) {
    EXPECT_LT(i, j);
    found.insert({i, j});
    ++visits;
  });
  EXPECT_EQ(visits, static_cast<int>(found.size())) << "a pair was visited twice";
  EXPECT_EQ(found, brute_force_pairs(x, radius));
  // for_each_near from every point gives the same pairs
  PairSet near;
  for (int i = 0; i < x.cols(); ++i)
    hash.for_each_near(x, i, radius, [&](int j) {
      EXPECT_GT(j, i);
      near.insert({i, j});
    });
  EXPECT_EQ(near, found);
}

Positions random_box(int n, const Vec3& extent, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  Positions x(3, n);
  for (int i = 0; i < n; ++i) x.col(i) = Vec3(u(rng), u(rng), u(rng)).cwiseProduct(extent);
  return x;
}

TEST(SpatialHash, DenseGridFindsExactlyTheBruteForcePairs) {
  // a cloud in a box a few cells wide: the dense layout
  const Positions x = random_box(600, Vec3(0.1, 0.1, 0.1), 1);
  SpatialHash hash;
  hash.build(x, 0.01);
  EXPECT_TRUE(hash.dense());
  expect_same_pairs(hash, x, 0.01);
  expect_same_pairs(hash, x, 0.006);  // radius below the cell size
}

TEST(SpatialHash, FlatSheetUsesTheDenseGrid) {
  // a thin sheet: one cell deep, so runs along z are clipped at both ends
  Positions x = random_box(900, Vec3(0.2, 0.2, 0.0), 2);
  SpatialHash hash;
  hash.build(x, 0.012);
  EXPECT_TRUE(hash.dense());
  expect_same_pairs(hash, x, 0.012);
}

TEST(SpatialHash, SpreadOutPointsUseTheHashedTable) {
  // clusters far apart: the box would hold far more cells than points
  Positions x = random_box(400, Vec3(0.05, 0.05, 0.05), 3);
  for (int i = 0; i < x.cols(); i += 2) x.col(i) += Vec3(40.0, -25.0, 13.0);
  SpatialHash hash;
  hash.build(x, 0.01);
  EXPECT_FALSE(hash.dense());
  expect_same_pairs(hash, x, 0.01);
}

TEST(SpatialHash, ThreadsBuildTheSameLayoutAndWalk) {
  // enough points for the box, the finite list and the counting sort to split among threads, in
  // both layouts, with non-finite points among them: the pairs come in the same order. A sheet's
  // grid has fewer cells than points (the sort's parts run on the threads); a thick box has 20
  // cells a point (dense, but sorted on one thread: a histogram per thread would cost more)
  enum class Layout { sheet, spread, thick };
  for (const Layout layout : {Layout::sheet, Layout::spread, Layout::thick}) {
    const bool spread = layout == Layout::spread;
    Positions x = random_box(20000, Vec3(1.2, 1.2, layout == Layout::thick ? 0.28 : 0.02), 5);
    if (spread) {
      for (int i = 0; i < x.cols(); i += 3) x.col(i) += Vec3(30.0, -20.0, 10.0);
    }
    for (int i = 7; i < x.cols(); i += 997) x(1, i) = std::numeric_limits<double>::quiet_NaN();
    std::vector<std::pair<int, int>> walks[3];
    for (int threads = 1; threads <= 3; ++threads) {
      SpatialHash hash;
      hash.build(x, 0.01, 0, threads);
      EXPECT_EQ(hash.dense(), !spread);
      hash.for_each_pair(x, 0.01, [&](int i, int j) { walks[threads - 1].push_back({i, j}); });
    }
    EXPECT_GT(walks[0].size(), 1000u);
    EXPECT_EQ(walks[1], walks[0]);
    EXPECT_EQ(walks[2], walks[0]);
  }
}

TEST(SpatialHash, NegativeCoordinatesAndCellBoundaries) {
  // points exactly on cell faces and on both sides of zero
  Positions x(3, 8);
  x << -0.01, 0.0, 0.01, -0.02, 0.02, 0.0, 0.005, -0.005,  //
      0.0, 0.0, 0.0, 0.01, -0.01, 0.0099, 0.0, 0.0,        //
      0.0, -0.01, 0.01, 0.0, 0.0, 0.0, -0.0051, 0.0049;
  SpatialHash hash;
  hash.build(x, 0.01);
  expect_same_pairs(hash, x, 0.0100001);
}

TEST(SpatialHash, NonFinitePointsAreInNoPair) {
  Positions x = random_box(200, Vec3(0.05, 0.05, 0.05), 4);
  x.col(7) = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  x.col(50).x() = std::numeric_limits<double>::infinity();
  SpatialHash hash;
  hash.build(x, 0.01);
  PairSet found;
  hash.for_each_pair(x, 0.01, [&](int i, int j) {
    EXPECT_NE(i, 7);
    EXPECT_NE(j, 7);
    EXPECT_NE(i, 50);
    EXPECT_NE(j, 50);
    found.insert({i, j});
  });
  PairSet expected;
  for (const auto& pair : brute_force_pairs(x, 0.01)) expected.insert(pair);  // NaN compares false
  for (auto it = expected.begin(); it != expected.end();) {
    it = (it->first == 50 || it->second == 50) ? expected.erase(it) : std::next(it);
  }
  EXPECT_EQ(found, expected);
}

TEST(SpatialHash, CoordinatesBeyondTheGridAreInNoPair) {
  // two clusters a kilometre apart (a sparse box: the hashed layout) and two rings flung past
  // what a cell key holds (a run blowing up): those two are in no pair and no query
  Positions x = random_box(200, Vec3(0.05, 0.05, 0.05), 5);
  for (int i = 100; i < 200; ++i) x(0, i) += 1000.0;
  x.col(3) = Vec3(1e300, 0.0, 0.0);
  x.col(4) = Vec3(0.0, -1e300, 0.0);
  SpatialHash hash;
  hash.build(x, 0.01);
  EXPECT_FALSE(hash.dense());
  PairSet found;
  hash.for_each_pair(x, 0.01, [&](int i, int j) { found.insert({i, j}); });
  PairSet expected;
  for (const auto& pair : brute_force_pairs(x, 0.01)) {
    if (pair.first != 3 && pair.first != 4 && pair.second != 3 && pair.second != 4)
      expected.insert(pair);
  }
  EXPECT_EQ(found, expected);
  int near_flung = 0;
  hash.for_each_near(x, 3, 0.01, [&](int) { ++near_flung; });
  EXPECT_EQ(near_flung, 0);
}

}  // namespace
}  // namespace chainmail

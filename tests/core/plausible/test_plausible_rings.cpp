// The plausible model's passes over every ring (core/plausible/plausible_rings): in either build of
// the lane kernels (portable, and AVX2 where the machine has it), the bits of the ring-by-ring
// oracle (plausible_rings_oracle.hpp), pinned rings untouched, and the moves from the contact
// list's anchor as a direct measurement gives them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/plausible/plausible_rings.hpp"
#include "core/plausible/plausible_rings_oracle.hpp"

namespace chainmail {
namespace {

struct Rings {
  std::vector<double> position, velocity, previous, push, inverse_mass;
  explicit Rings(int n, std::mt19937& random)
      : position(3 * n), velocity(3 * n), previous(3 * n), push(n, 1.0), inverse_mass(n) {
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    for (double& v : position) v = value(random);
    for (double& v : velocity) v = value(random);
    for (double& v : previous) v = value(random);
    for (int i = 0; i < n; ++i) inverse_mass[i] = i % 5 == 3 ? 0.0 : 1.0 + value(random);
  }
  RingArrays arrays() {
    return {position.data(), velocity.data(), previous.data(), push.data(), inverse_mass.data()};
  }
};

bool same_bits(const std::vector<double>& x, const std::vector<double>& y) {
  return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
}

TEST(PlausibleRings, VectorPredictionAndMovesGiveTheScalarBits) {
  // 4 groups and a tail of 3 rings, every fifth pinned, one NaN coordinate in the anchor
  constexpr int kRings = 19;
  std::mt19937 random(3);
  const Rings start(kRings, random);
  std::vector<double> anchor = Rings(kRings, random).position;
  anchor[3 * 14 + 1] = std::numeric_limits<double>::quiet_NaN();  // in the last group of four
  const Vec3 fall(0.01, -0.0392, 0.002);                          // m/s
  for (int begin : {0, 1, 4, 16}) {
    Rings scalar = start;
    const RingMoves a =
        oracle::predict_rings(scalar.arrays(), fall, 0.004, begin, kRings, anchor.data());
    for (bool avx2 : {false, true}) {
      Rings vector = start;
      const RingMoves b =
          predict_rings(vector.arrays(), fall, 0.004, begin, kRings, avx2, anchor.data());
      EXPECT_TRUE(same_bits(scalar.position, vector.position)) << avx2;
      EXPECT_TRUE(same_bits(scalar.velocity, vector.velocity)) << avx2;
      EXPECT_TRUE(same_bits(scalar.previous, vector.previous)) << avx2;
      EXPECT_TRUE(same_bits(scalar.push, vector.push)) << avx2;
      EXPECT_EQ(a.farthest2, b.farthest2) << avx2;
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(a.lo[c], b.lo[c]) << avx2;
        EXPECT_EQ(a.hi[c], b.hi[c]) << avx2;
      }
    }
    // (the lanes' bits are the oracle's:) pinned rings keep position and velocity; rings before
    // begin are untouched
    for (int i = 0; i < kRings; ++i) {
      const bool moved = i >= begin && start.inverse_mass[i] != 0.0;
      EXPECT_EQ(scalar.position[3 * i] != start.position[3 * i], moved) << i;
      EXPECT_EQ(scalar.push[i], i >= begin ? 0.0 : 1.0) << i;
    }
    // the moves, measured directly from the new positions (the NaN left out, as std::max and
    // std::min leave it)
    double farthest2 = 0.0;
    double lo = std::numeric_limits<double>::infinity();
    for (int i = begin; i < kRings; ++i) {
      const double dx = scalar.position[3 * i] - anchor[3 * i];
      const double dy = scalar.position[3 * i + 1] - anchor[3 * i + 1];
      const double dz = scalar.position[3 * i + 2] - anchor[3 * i + 2];
      farthest2 = std::max(farthest2, (dx * dx + dy * dy) + dz * dz);
      lo = std::min(lo, dx);
    }
    EXPECT_EQ(a.farthest2, farthest2);
    EXPECT_EQ(a.lo[0], lo);
  }
}

TEST(PlausibleRings, VectorVelocitiesGiveTheScalarBits) {
  constexpr int kRings = 23;
  std::mt19937 random(5);
  const Rings start(kRings, random);
  Rings scalar = start;
  oracle::update_ring_velocities(scalar.arrays(), 0.004, 2, kRings);
  for (bool avx2 : {false, true}) {
    Rings vector = start;
    update_ring_velocities(vector.arrays(), 0.004, 2, kRings, avx2);
    EXPECT_TRUE(same_bits(scalar.velocity, vector.velocity)) << avx2;
    EXPECT_TRUE(same_bits(start.position, vector.position)) << avx2;
    EXPECT_TRUE(same_bits(start.push, vector.push)) << avx2;
  }
  for (int i = 2; i < kRings; ++i) {
    for (int c = 0; c < 3; ++c) {
      const double expected = start.inverse_mass[i] == 0.0
                                  ? 0.0
                                  : (start.position[3 * i + c] - start.previous[3 * i + c]) / 0.004;
      EXPECT_EQ(scalar.velocity[3 * i + c], expected) << i;
    }
  }
  EXPECT_EQ(scalar.velocity[0], start.velocity[0]);  // before begin: untouched
}

TEST(PlausibleRings, VelocitiesAndPredictionInOnePassGiveTheTwoPassesBits) {
  // the velocity update then the prediction, one pass each (the oracle's), against both in one
  // pass in either build of the lanes: groups of four and a tail, pinned rings, a NaN in the
  // positions
  constexpr int kRings = 21;
  std::mt19937 random(9);
  Rings start(kRings, random);
  start.position[3 * 9 + 2] = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> anchor = Rings(kRings, random).position;
  const Vec3 fall(0.0, -0.0392, 0.001);  // m/s
  for (int begin : {0, 3}) {
    Rings two = start;
    oracle::update_ring_velocities(two.arrays(), 0.004, begin, kRings);
    const RingMoves a =
        oracle::predict_rings(two.arrays(), fall, 0.004, begin, kRings, anchor.data());
    for (bool vector : {false, true}) {
      Rings one = start;
      const RingMoves b = update_velocities_and_predict(one.arrays(), fall, 0.004, begin, kRings,
                                                        vector, anchor.data());
      EXPECT_TRUE(same_bits(two.position, one.position)) << vector;
      EXPECT_TRUE(same_bits(two.velocity, one.velocity)) << vector;
      EXPECT_TRUE(same_bits(two.previous, one.previous)) << vector;
      EXPECT_TRUE(same_bits(two.push, one.push)) << vector;
      EXPECT_EQ(a.farthest2, b.farthest2) << vector;
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(a.lo[c], b.lo[c]) << vector;
        EXPECT_EQ(a.hi[c], b.hi[c]) << vector;
      }
    }
    // a free ring's new velocity is its move over the substep before plus gravity's step
    const int i = begin + 1;
    ASSERT_NE(start.inverse_mass[i], 0.0);
    EXPECT_EQ(two.velocity[3 * i + 1],
              (start.position[3 * i + 1] - start.previous[3 * i + 1]) / 0.004 + fall.y());
  }
}

}  // namespace
}  // namespace chainmail

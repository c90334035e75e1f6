// The sweeps' blocks of four pairs (core/plausible/plausible_blocks): which pairs make a block, and
// that a block's lanes, in either build of the kernels (portable, and AVX2 where the machine has
// it), give the bits of the scalar constraint functions, pair by pair, on stretched, compressed,
// degenerate and NaN pairs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/plausible/plausible_blocks.hpp"
#include "core/plausible/plausible_lanes.hpp"
#include "core/plausible/plausible_sweep.hpp"

namespace chainmail {
namespace {

// the same bits, a NaN for a NaN (which of two NaN operands an instruction passes on, and so
// its sign, depends on the operands' order, which the compiler chooses)
bool same_bits(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size()) return false;
  for (size_t i = 0; i < x.size(); ++i) {
    if (std::isnan(x[i]) && std::isnan(y[i])) continue;
    if (std::memcmp(&x[i], &y[i], sizeof(double)) != 0) return false;
  }
  return true;
}

TEST(PlausibleBlocks, TheVectorHookPicksTheLaneBuild) {
  // off: the portable build (what the comparisons below rely on); on: AVX2 where the machine has
  // it, a build of its own
  EXPECT_EQ(&lane_kernels(false), &kScalarLaneKernels);
#if defined(CHAINMAIL_AVX2_SWEEPS)
  EXPECT_EQ(&lane_kernels(true),
            vector_sweeps_available() ? &kAvx2LaneKernels : &kScalarLaneKernels);
  EXPECT_NE(kAvx2LaneKernels.sweep_pair_blocks, kScalarLaneKernels.sweep_pair_blocks);
  EXPECT_NE(kAvx2LaneKernels.predict_rings, kScalarLaneKernels.predict_rings);
#endif
}

TEST(PlausibleBlocks, FourPairsMakeABlockOnlyAsARunOrAnAdjacentSetWithoutPins) {
  const std::vector<double> w = {0.0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  std::vector<EdgeConstraint> pairs = {
      {4, 12, 0.1, 1.0},  {5, 13, 0.1, 1.0},  {6, 14, 0.2, 1.0},  {7, 15, 0.1, 1.0},   // run
      {8, 9, 0.1, 1.0},   {10, 11, 0.1, 1.0}, {12, 13, 0.1, 1.0}, {14, 15, 0.1, 1.0},  // adjacent
      {0, 16, 0.1, 1.0},  {1, 17, 0.1, 1.0},  {2, 18, 0.1, 1.0},  {3, 19, 0.1, 1.0},   // a pin
      {1, 3, 0.1, 1.0},   {2, 4, 0.1, 1.0},   {3, 5, 0.1, 1.0},   {4, 6, 0.1, 1.0},    // overlap
      {16, 17, 0.1, 1.0}, {18, 19, 0.1, 1.0}};                                         // too few
  const std::vector<PairBlock> blocks =
      make_pair_blocks(pairs.data(), 0, static_cast<int>(pairs.size()), w);
  ASSERT_EQ(blocks.size(), 2u + 4 + 4 + 2);
  EXPECT_EQ(blocks[0].kind, PairBlock::Kind::run);
  EXPECT_FALSE(blocks[0].shared_bounds);  // the third pair's minimum differs
  EXPECT_EQ(blocks[1].kind, PairBlock::Kind::adjacent);
  EXPECT_TRUE(blocks[1].shared_bounds);
  // every pair once, in order
  int next = 0;
  for (const PairBlock& block : blocks) {
    EXPECT_EQ(block.pair, next);
    EXPECT_EQ(block.groups, 1);
    next += block.pairs();
  }
  EXPECT_EQ(next, static_cast<int>(pairs.size()));
  for (size_t k = 2; k < blocks.size(); ++k) EXPECT_EQ(blocks[k].kind, PairBlock::Kind::single);
}

TEST(PlausibleBlocks, GroupsThatContinueEachOtherMakeOneBlock) {
  // a run of 12 pairs (r, r + 16) with shared bounds is one block of three groups; the next run
  // continues it in rings but not in bounds, the adjacent sets after continue each other (8 rings
  // further on) until one moves a pin
  std::vector<double> w(64, 1.0);
  w[60] = 0.0;
  std::vector<EdgeConstraint> pairs;
  for (int r = 0; r < 12; ++r) pairs.push_back({r, r + 16, 0.1, 1.0});
  for (int r = 12; r < 16; ++r) pairs.push_back({r, r + 16, 0.1, 0.9});
  for (int r = 32; r < 64; r += 2) pairs.push_back({r, r + 1, 0.1, 1.0});
  const std::vector<PairBlock> blocks =
      make_pair_blocks(pairs.data(), 0, static_cast<int>(pairs.size()), w);
  ASSERT_EQ(blocks.size(), 3u + 4);
  EXPECT_EQ(blocks[0].kind, PairBlock::Kind::run);
  EXPECT_EQ(blocks[0].groups, 3);
  EXPECT_EQ(blocks[1].kind, PairBlock::Kind::run);
  EXPECT_EQ(blocks[1].groups, 1);
  EXPECT_EQ(blocks[2].kind, PairBlock::Kind::adjacent);
  EXPECT_EQ(blocks[2].a, 32);
  EXPECT_EQ(blocks[2].groups, 3);  // rings 32..55; the fourth set holds the pin at 60
  for (size_t k = 3; k < blocks.size(); ++k) EXPECT_EQ(blocks[k].kind, PairBlock::Kind::single);
  int next = 0;
  for (const PairBlock& block : blocks) {
    EXPECT_EQ(block.pair, next);
    next += block.pairs();
  }
  EXPECT_EQ(next, static_cast<int>(pairs.size()));
}

// positions of `rings` rings near a lattice, each pair set to one of the cases the lanes must
// treat as the scalar code does
std::vector<double> case_positions(int rings, const std::vector<EdgeConstraint>& pairs,
                                   std::mt19937& random) {
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  std::vector<double> x(3 * static_cast<size_t>(rings));
  for (int r = 0; r < rings; ++r) {
    for (int c = 0; c < 3; ++c) x[3 * r + c] = 0.5 * (r % 7) + jitter(random) + c;
  }
  for (size_t k = 0; k < pairs.size(); ++k) {
    double* const a = &x[3 * pairs[k].a];
    double* const b = &x[3 * pairs[k].b];
    switch (k % 6) {
      case 0:  // exactly at the maximum along x: within bounds
        b[0] = a[0] + pairs[k].max_length, b[1] = a[1], b[2] = a[2];
        break;
      case 1:  // on top of each other: degenerate, left alone
        b[0] = a[0], b[1] = a[1], b[2] = a[2];
        break;
      case 2:  // stretched
        b[0] = a[0] + 3.0 * pairs[k].max_length, b[1] = a[1] + 0.1, b[2] = a[2];
        break;
      case 3:  // compressed
        b[0] = a[0] + 0.5 * pairs[k].min_length, b[1] = a[1], b[2] = a[2] + 0.01;
        break;
      default:  // as jittered
        break;
    }
  }
  return x;
}

TEST(PlausibleBlocks, BlocksGiveTheScalarSweepsBits) {
  // runs (r, r + 8), (r, r + 16), (r, r + 40) and adjacent pairs over 64 rings, one pinned, one
  // with a NaN: swept as blocks and pair by pair, many times over random cases, the same bits and
  // the same violation
  constexpr int kRings = 64;
  std::vector<double> w(kRings);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> weight(0.5, 2.0);
  for (double& v : w) v = weight(random);
  w[5] = 0.0;  // a pin: its blocks become singles
  std::vector<EdgeConstraint> pairs;
  for (int r = 0; r < 8; ++r) pairs.push_back({r, r + 8, 0.3, 0.9});
  for (int r = 16; r < 32; ++r) pairs.push_back({r, r + 16, 0.2 + 0.1 * (r % 2), 0.8});
  for (int r = 48; r < 64; r += 2) pairs.push_back({r, r + 1, 0.3, 0.9});
  for (int r = 8; r < 16; ++r) pairs.push_back({r, r + 40, 0.3, 0.9});  // a block of two groups
  const int count = static_cast<int>(pairs.size());
  const std::vector<PairBlock> blocks = make_pair_blocks(pairs.data(), 0, count, w);
  int vectored = 0;  // groups of four
  for (const PairBlock& block : blocks) {
    if (block.kind != PairBlock::Kind::single) vectored += block.groups;
  }
  EXPECT_EQ(vectored, 9);            // the pinned run's first block stays four singles
  EXPECT_LT(blocks.size(), 9u + 4);  // groups that continue each other made one block
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> scalar = case_positions(kRings, pairs, random);
    if (trial % 10 == 0) scalar[3 * 20 + 1] = std::numeric_limits<double>::quiet_NaN();
    const std::vector<double> start = scalar;
    double scalar_worst = 0.0;
    for (const EdgeConstraint& e : pairs) {
      scalar_worst = std::max(scalar_worst, sweep_pair(scalar.data(), w.data(), e));
    }
    for (bool avx2 : {false, true}) {
      std::vector<double> blocked = start;
      const double blocked_worst =
          sweep_pair_blocks(blocked.data(), w.data(), pairs.data(), blocks.data(),
                            static_cast<int>(blocks.size()), avx2);
      ASSERT_TRUE(same_bits(scalar, blocked)) << "trial " << trial << " avx2 " << avx2;
      ASSERT_EQ(scalar_worst, blocked_worst) << "trial " << trial << " avx2 " << avx2;
    }
  }
}

TEST(PlausibleBlocks, AttachmentRunsGiveTheScalarSweepsBits) {
  // rings 8..39 attached to pins 0..15 (some runs broken by a missing ring), reaches that leave
  // some rings inside and some out, and a NaN ring: the same bits and violation. Every other
  // trial the runs hang from four consecutive pins (rings along a pinned edge), the others from
  // scattered ones: the two ways a run loads its pins
  constexpr int kRings = 40;
  std::mt19937 random(11);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0), reach(0.2, 1.5);
  int long_blocks[2] = {0, 0};  // blocks of two groups or more: scattered pins, consecutive pins
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<PinAttachment> list;
    for (int ring = 8; ring < kRings; ++ring) {
      if (ring % 11 == 0) continue;
      list.push_back({ring, trial % 2 == 0 ? ring % 16 : ring * 5 % 8, reach(random)});
    }
    std::vector<double> scalar(3 * kRings);
    for (double& v : scalar) v = coordinate(random);
    if (trial % 10 == 0) scalar[3 * 17 + 2] = std::numeric_limits<double>::quiet_NaN();
    const std::vector<double> start = scalar;
    double scalar_worst = 0.0;
    for (const PinAttachment& a : list) {
      scalar_worst = std::max(scalar_worst, sweep_attachment(scalar.data(), a));
    }
    const std::vector<AttachmentBlock> blocks =
        make_attachment_blocks(list.data(), 0, static_cast<int>(list.size()));
    for (const AttachmentBlock& block : blocks) long_blocks[block.pin_run] += block.groups >= 2;
    std::vector<double> reaches;
    for (const PinAttachment& a : list) reaches.push_back(a.max_distance);
    for (bool avx2 : {false, true}) {
      std::vector<double> blocked = start;
      const double blocked_worst =
          sweep_attachment_blocks(blocked.data(), list.data(), reaches.data(), blocks.data(),
                                  static_cast<int>(blocks.size()), avx2);
      ASSERT_TRUE(same_bits(scalar, blocked)) << "trial " << trial << " avx2 " << avx2;
      ASSERT_EQ(scalar_worst, blocked_worst) << "trial " << trial << " avx2 " << avx2;
    }
  }
  EXPECT_GT(long_blocks[0], 0);
  EXPECT_GT(long_blocks[1], 0);
}

TEST(PlausibleBlocks, AttachmentsOfConsecutiveRingsMakeGroupsAndBlocks) {
  // rings 10..21 from pins 0..11 (three groups, one block), rings 22..29 from scattered pins (two
  // groups, one block), ring 31 alone (30 is missing, so 31, 33, 34, 35 are not consecutive),
  // rings 33..36 from pins 12..15 (a group of consecutive pins, not after the first block)
  std::vector<PinAttachment> list;
  for (int ring = 10; ring < 22; ++ring) list.push_back({ring, ring - 10, 1.0});
  for (int ring = 22; ring < 30; ++ring) list.push_back({ring, ring * 5 % 8, 1.0});
  list.push_back({31, 0, 1.0});
  for (int ring = 33; ring < 37; ++ring) list.push_back({ring, ring - 21, 1.0});
  const std::vector<AttachmentBlock> blocks =
      make_attachment_blocks(list.data(), 0, static_cast<int>(list.size()));
  ASSERT_EQ(blocks.size(), 4u);
  EXPECT_EQ(blocks[0].groups, 3);
  EXPECT_TRUE(blocks[0].pin_run);
  EXPECT_EQ(blocks[1].groups, 2);
  EXPECT_FALSE(blocks[1].pin_run);
  EXPECT_EQ(blocks[2].groups, 0);
  EXPECT_EQ(blocks[3].groups, 1);
  EXPECT_TRUE(blocks[3].pin_run);
  int next = 0;
  for (const AttachmentBlock& block : blocks) {
    EXPECT_EQ(block.item, next);
    next += block.items();
  }
  EXPECT_EQ(next, static_cast<int>(list.size()));
}

}  // namespace
}  // namespace chainmail

// The blocks of four pairs (core/plausible/plausible_blocks.hpp): their making, and the choice of
// the lane kernels that sweep them (core/plausible/plausible_blocks_kernel.hpp) at run time, so a
// portable build uses AVX2 too where the machine has it.
#include "core/plausible/plausible_blocks.hpp"

#include <algorithm>
#include <cstdlib>

#include "core/plausible/plausible_lanes.hpp"

namespace chainmail {
namespace {

bool same_bounds(const EdgeConstraint& x, const EdgeConstraint& y) {
  return x.min_length == y.min_length && x.max_length == y.max_length;
}

PairBlock::Kind block_kind(const EdgeConstraint* f) {
  const int a = f[0].a, b = f[0].b;
  bool run = std::abs(b - a) >= 4;  // the two runs of rings do not overlap
  bool adjacent = b == a + 1;
  for (int i = 1; i < 4; ++i) {
    run = run && f[i].a == a + i && f[i].b == b + i;
    adjacent = adjacent && f[i].a == a + 2 * i && f[i].b == a + 2 * i + 1;
  }
  if (run) return PairBlock::Kind::run;
  if (adjacent) return PairBlock::Kind::adjacent;
  return PairBlock::Kind::single;
}

// `next` is one more group of `last`: the same kind and shared bounds, its rings and pairs where
// last's next group's would be
bool continues(const PairBlock& last, const PairBlock& next) {
  if (last.kind == PairBlock::Kind::single || next.kind != last.kind) return false;
  if (!last.shared_bounds || !next.shared_bounds) return false;
  if (next.min_length != last.min_length || next.max_length != last.max_length) return false;
  const int rings = last.kind == PairBlock::Kind::run ? 4 : 8;  // a group's, on each side
  return next.a == last.a + rings * last.groups && next.b == last.b + rings * last.groups &&
         next.pair == last.pair + 4 * last.groups;
}

}  // namespace

bool vector_sweeps_available() {
#if defined(CHAINMAIL_AVX2_SWEEPS)
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

std::vector<PairBlock> make_pair_blocks(const EdgeConstraint* pairs, int begin, int end,
                                        const std::vector<double>& inverse_mass) {
  std::vector<PairBlock> blocks;
  for (int k = begin; k < end;) {
    const EdgeConstraint* f = pairs + k;
    PairBlock block{f->a, f->b, PairBlock::Kind::single, k, 1, true, f->min_length, f->max_length};
    if (k + 4 <= end) {
      const PairBlock::Kind kind = block_kind(f);
      bool fits = kind != PairBlock::Kind::single;
      for (int i = 0; i < 4 && fits; ++i) {
        fits = inverse_mass[f[i].a] != 0.0 && inverse_mass[f[i].b] != 0.0;
        block.shared_bounds = block.shared_bounds && same_bounds(f[i], f[0]);
      }
      if (fits) block.kind = kind;
    }
    k += block.pairs();
    if (!blocks.empty() && continues(blocks.back(), block)) {
      ++blocks.back().groups;
    } else {
      blocks.push_back(block);
    }
  }
  return blocks;
}

std::vector<AttachmentBlock> make_attachment_blocks(const PinAttachment* list, int begin, int end) {
  std::vector<AttachmentBlock> blocks;
  for (int k = begin; k < end;) {
    const PinAttachment* f = list + k;
    AttachmentBlock block{k, 0, false};
    // one ring at most once, sorted by ring: four items three rings apart are consecutive rings
    if (k + 4 <= end && f[3].ring == f[0].ring + 3) {
      block.groups = 1;
      block.pin_run =
          f[1].pin == f[0].pin + 1 && f[2].pin == f[0].pin + 2 && f[3].pin == f[0].pin + 3;
    }
    k += block.items();
    AttachmentBlock* last = blocks.empty() ? nullptr : &blocks.back();
    if (last && last->groups > 0 && block.groups > 0 && block.pin_run == last->pin_run &&
        f->ring == list[last->item].ring + 4 * last->groups &&
        (!block.pin_run || f->pin == list[last->item].pin + 4 * last->groups)) {
      ++last->groups;
    } else {
      blocks.push_back(block);
    }
  }
  return blocks;
}

const LaneKernels& lane_kernels(bool vector) {
#if defined(CHAINMAIL_AVX2_SWEEPS)
  if (vector && vector_sweeps_available()) return kAvx2LaneKernels;
#endif
  (void)vector;
  return kScalarLaneKernels;
}

double sweep_pair_blocks(double* x, const double* w, const EdgeConstraint* pairs,
                         const PairBlock* blocks, int count, bool vector) {
  return lane_kernels(vector).sweep_pair_blocks(x, w, pairs, blocks, count);
}

double sweep_attachment_blocks(double* x, const PinAttachment* list, const double* reach,
                               const AttachmentBlock* blocks, int count, bool vector) {
  return lane_kernels(vector).sweep_attachment_blocks(x, list, reach, blocks, count);
}

}  // namespace chainmail

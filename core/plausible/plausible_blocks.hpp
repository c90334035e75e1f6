// A sweep stage's pairs in blocks of four, solved four at a time in SIMD lanes. A regular weave's
// colours are runs of pairs a fixed ring offset apart, (r, r + k) for consecutive r, and the
// horizontal pairs (r, r + 1) for every other r: four such pairs read and write 4 (or 8)
// consecutive rings, so their positions load as whole vectors instead of one scalar at a time.
// A block does per lane exactly the arithmetic of solve_edge_constraint (no fused multiply-add,
// the same order of operations; square root and division are correctly rounded in both), and a
// colour's pairs share no ring, so the blocks give the scalar sweep's bits. The lanes are AVX2
// where the machine has it, else portable (core/plausible/lanes.hpp), with the same bits; `vector`
// false asks for the portable lanes anyway (a hook for tests and benchmarks).
#pragma once

#include <vector>

#include "core/plausible/pin_attachments.hpp"
#include "core/plausible/sweep_records.hpp"

namespace chainmail {

// whether this machine runs the AVX2 lane kernels (x86 with AVX2; elsewhere the portable lanes)
bool vector_sweeps_available();

// pairs [begin, end) of one stage (no two share a ring) as blocks, in order: four pairs make a
// group when they form a run or an adjacent set and move no pin (a pin is never written, and
// another thread may be reading it), and groups that continue each other with the same bounds
// one block; the others are singles
std::vector<PairBlock> make_pair_blocks(const EdgeConstraint* pairs, int begin, int end,
                                        const std::vector<double>& inverse_mass);

// one sweep over blocks [0, count); the largest violation met, m (as the scalar sweep's)
double sweep_pair_blocks(double* x, const double* w, const EdgeConstraint* pairs,
                         const PairBlock* blocks, int count, bool vector = true);

// attachments [begin, end) of one list (a ring at most once, sorted by ring) as blocks, in order:
// four attachments of consecutive rings make a group, and groups that continue each other (in
// rings, and in pins where their pins are consecutive) one block; the others are alone
std::vector<AttachmentBlock> make_attachment_blocks(const PinAttachment* list, int begin, int end);

// one sweep over blocks [0, count) of `list`, whose max_distance `reach` also holds in the list's
// order: each group's four in lanes; the largest violation met, m (as the scalar sweep's)
double sweep_attachment_blocks(double* x, const PinAttachment* list, const double* reach,
                               const AttachmentBlock* blocks, int count, bool vector = true);

}  // namespace chainmail

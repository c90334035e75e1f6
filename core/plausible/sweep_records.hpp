// The records the plausible model's sweeps run over: edge constraints, the pairs and attachments
// in blocks of four lanes, and the bands that split a sweep between threads.
#pragma once

#include <vector>

namespace chainmail {

// one Provot edge: a plain record, solved by solve_edge_constraint
struct EdgeConstraint {
  int a, b;
  double min_length;  // m
  double max_length;  // m
};

// four pairs of a stage solved together in SIMD lanes (core/plausible/plausible_blocks), or one
// alone
struct PairBlock {
  enum class Kind : int {
    single,    // pairs[pair] alone (scalar)
    run,       // (a + i, b + i), i = 0..3, the two runs of rings apart
    adjacent,  // (a + 2 i, a + 2 i + 1), i = 0..3: rings a .. a + 7
  };
  int a = 0, b = 0;  // the first pair's rings
  Kind kind = Kind::single;
  int pair = 0;  // the first pair's index in the stage's list
  // run or adjacent with shared bounds: groups of four, each continuing the last (its rings 4,
  // or for adjacent sets 8, further on, its pairs the next four), solved one after the other
  // without reading another block (a regular weave's colours run along whole rows)
  int groups = 1;
  // m, the four pairs' bounds where they share them (else read from the pairs)
  bool shared_bounds = true;
  double min_length = 0.0, max_length = 0.0;
  int pairs() const { return kind == Kind::single ? 1 : 4 * groups; }
};

// a long-range attachment of a sweep's list alone, or groups of four attachments of consecutive
// rings solved together in SIMD lanes (core/plausible/plausible_blocks)
struct AttachmentBlock {
  int item = 0;  // the first attachment's index in its list
  // groups of four consecutive rings, each continuing the last (its rings 4 further on, its
  // attachments the next four); 0: the item alone
  int groups = 0;
  // each group's four pins are consecutive rings too, each group's 4 on from the last's (rings
  // along a pinned edge hang from the pins along it)
  bool pin_run = false;
  int items() const { return groups == 0 ? 1 : 4 * groups; }
};

// the sweep's attachments, edges and diagonals as stages (an attachment list, a colour) cut into
// bands of consecutive rings (core/plausible/plausible_bands.cpp), each band at least as wide as
// the farthest any pair reaches (|a - b|): a pair joins its lower ring's band to itself or the
// next. Each thread takes a run of bands through the stages in order and waits only where a
// neighbouring band of another thread has not finished the stage before; the result is that of
// the coloured sweep, stage after stage over the whole sheet
struct SweepBands {
  enum class Kind { attachments, edges, diagonals };
  struct Stage {
    Kind kind = Kind::edges;
    int list = 0;                 // attachments: which list
    std::vector<int> band_start;  // (bands + 1) the stage's items of each band, into its list
    // edges and diagonals: the stage's pairs as blocks, band by band
    std::vector<PairBlock> blocks;
    std::vector<int> block_start;  // (bands + 1) each band's blocks, into (attachment_)blocks
    // attachments: the list's items as blocks, band by band, and their max_distance in the
    // list's order (m: four load as one vector)
    std::vector<AttachmentBlock> attachment_blocks;
    std::vector<double> reach;
  };
  std::vector<int> first_ring;  // (bands + 1)
  std::vector<Stage> stages;    // in the sweep's order
  int bands() const { return static_cast<int>(first_ring.size()) - 1; }
};

}  // namespace chainmail

// How close the rings of a 4-in-1 sheet can come, from the ring geometry. A linked neighbour
// (i +- 1, j), (i, j +- 1) can come nearly as close as the wire thickness, but two rings that share
// two neighbours meet sooner: (i +- 1, j +- 1) sit side by side in one row and stack like leaning
// coins, (i +- 1, j -+ 1) sit two rows apart in one column and meet rim to rim; (i +- 2, j +- 1),
// (i +- 1, j +- 2) (signs alike) sit in adjacent rows a row and a half apart and would pass
// through each other when a row is pushed together along itself. Those limits keep a sheet from
// folding up like lazy tongs, which the neighbour distances alone allow: a rhombus of four links
// with sides at most L can have one diagonal near 0 and the other near 2L.
#pragma once

#include <vector>

#include "core/ring.hpp"
#include "core/types.hpp"
#include "core/weave.hpp"

namespace chainmail {

// the smallest centre distance d <= |offset| such that a ring with orientation `first` at the
// origin and one with orientation `second` at d * offset / |offset| keep their tori clear (centre
// circles at least 2a apart) for every distance from d up to |offset|, and stay linked when
// `linked`; found by a scan inward from |offset| and bisection. |offset| when the pair is not
// valid there. m
double closest_approach(const RingGeometry& ring, const Quat& first, const Quat& second,
                        const Vec3& offset, bool linked);

// how close (and for rings in one row, how far apart) each kind of pair of a 4-in-1 sheet can be,
// for rings leaning by +-lean about the row normal (the model's swivel at full extension), moved
// along the lines the rest layout places them on. m
struct WeaveLimits {
  // closest linked neighbours (i +- 1, j), (i, j +- 1); 2a where the rest layout is not clear
  double link = 0.0;
  double row = 0.0;     // closest (i +- 1, j +- 1), side by side in one row: leaning coins
  double column = 0.0;  // closest (i +- 1, j -+ 1), two rows apart in one column: rim to rim
  // the same where either ring lies in the sheet's first or last row: linked to one row only, it
  // turns about its links out of the sheet's plane, and keeps only the knights' rule, 2c
  double column_edge = 0.0;
  // the farthest (i +- 1, j +- 1): the two links to a ring they share at their reach in their
  // direction (four_in_one_link_reach) while the column is at its closest; infinite where the
  // links have no reach
  double row_max = 0.0;
  // closest (i +- 2, j +- 1), (i +- 1, j +- 2) (signs alike): rings of adjacent rows a row and a
  // half apart, which a row pushed together along itself brings toward each other; 2c, the
  // closest two rings can come and not pass through each other whatever their orientations
  double knight = 0.0;
};
WeaveLimits four_in_one_limits(const RingGeometry& ring, double lean);

// a pair of rings that share two neighbours, with its distance bounds
struct DiagonalPair {
  int a, b;         // a < b
  double min, max;  // m
};
// every (i, j)-(i + 1, j + 1) and (i, j)-(i + 1, j - 1) pair of a 4-in-1 weave (none otherwise);
// a column pair with a ring of the sheet's first or last row is kept limits.column_edge apart
std::vector<DiagonalPair> diagonal_pairs(const Weave& weave, const WeaveLimits& limits);
// every (i, j)-(i + 2, j + 1) and (i, j)-(i + 1, j + 2) pair of a 4-in-1 weave, kept at least
// limits.knight apart (none otherwise)
std::vector<DiagonalPair> knight_pairs(const Weave& weave, const WeaveLimits& limits);

}  // namespace chainmail

#include "core/plausible/weave_limits.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/geometry.hpp"
#include "core/plausible/link_distance.hpp"

namespace chainmail {
namespace {

// the in-row distance of two rings whose links to the ring they share, at angle alpha from the
// row, are at their reach; rises as alpha falls toward the row while the column distance
// 2 reach sin(alpha) falls: the widest row is where the column reaches its closest. m
double widest_row(const RingGeometry& ring, double lean, double column) {
  auto column_at = [&](double alpha) {
    return 2.0 * four_in_one_link_reach(ring, lean, alpha) * std::sin(alpha);
  };
  double hi = 0.5 * std::numbers::pi;  // column_at(hi) = 2 ID > column
  if (column_at(hi) <= column) return std::numeric_limits<double>::infinity();
  double lo = hi;
  while (lo > 0.0 && column_at(lo) > column) lo -= 0.01 * std::numbers::pi;
  if (lo <= 0.0) return std::numeric_limits<double>::infinity();
  for (int it = 0; it < 40; ++it) {
    const double mid = 0.5 * (lo + hi);
    (column_at(mid) > column ? hi : lo) = mid;
  }
  return 2.0 * four_in_one_link_reach(ring, lean, hi) * std::cos(hi);
}

}  // namespace

double closest_approach(const RingGeometry& ring, const Quat& first, const Quat& second,
                        const Vec3& offset, bool linked) {
  const double c = ring.centre_radius, a = ring.wire_radius;
  const double start = offset.norm();
  const Vec3 u = offset / start;
  const Circle one = ring_circle(Vec3::Zero(), first, c);
  auto valid = [&](double d) {
    const Circle other = ring_circle(d * u, second, c);
    if (linked && !circles_linked(one, other)) return false;
    return !circles_closer_than(one, other, 2.0 * a).has_value();
  };
  if (!valid(start)) return start;
  // scan inward to the first invalid distance, then bisect the step before it
  constexpr int kScan = 200;
  const double step = start / kScan;
  for (int k = 1; k <= kScan; ++k) {
    const double d = start - k * step;
    if (valid(d)) continue;
    double lo = d, hi = d + step;  // lo not valid, hi valid
    for (int it = 0; it < 40; ++it) {
      const double mid = 0.5 * (lo + hi);
      (valid(mid) ? hi : lo) = mid;
    }
    return hi;
  }
  return 0.0;
}

WeaveLimits four_in_one_limits(const RingGeometry& ring, double lean) {
  // sheet frame: rows along X, rows advance along Z, sheet normal Y; a ring leans by +lean about
  // the row normal (Z), the rows before and after it by -lean; rest offsets from the weave
  const double inner = ring.inner_diameter();
  const double along = kFourInOneRowSpacing * inner, advance = kFourInOneRowAdvance * inner;
  const Quat mine(Eigen::AngleAxisd(lean, Vec3::UnitZ()));
  const Quat theirs(Eigen::AngleAxisd(-lean, Vec3::UnitZ()));
  WeaveLimits limits;
  // a pair that is not clear even at its rest distance (the paper's swivel a/c turns neighbours
  // nearly into one plane) keeps the rest distance as its closest, links the wire thickness
  const Vec3 link(0.5 * along, 0.0, advance);
  limits.link = closest_approach(ring, mine, theirs, link, true);
  if (limits.link >= link.norm()) limits.link = ring.min_link_distance();
  limits.row = closest_approach(ring, mine, mine, Vec3(along, 0.0, 0.0), false);
  limits.column = closest_approach(ring, mine, mine, Vec3(0.0, 0.0, 2.0 * advance), false);
  limits.row_max = widest_row(ring, lean, limits.column);
  // rings of adjacent rows a row and a half apart: whatever way they turn, circles of radius c
  // whose centres are 2c apart cannot link (rigid rings, which turn out of each other's way, keep
  // 1.2 to 1.3 ID in a corner-hung sheet; the tori of rings at the extended swivel touch at 1.31)
  limits.knight = 2.0 * ring.centre_radius;
  // links to the rows on both sides hold a ring in the sheet's plane, rim to rim; a ring of the
  // first or last row, hinged on the links to its one row, turns out of the plane and past its
  // column neighbour's rim (a ring at a row's end still has both rows: it keeps the rim)
  limits.column_edge = std::min(limits.column, limits.knight);
  return limits;
}

namespace {

// (i, j) -> ring over a weave's grid, -1 outside it or where no ring is
struct GridIndex {
  int rows_i = 0, cols_j = 0;
  std::vector<int> index;
  explicit GridIndex(const Weave& weave) {
    for (const auto& g : weave.grid) {
      rows_i = std::max(rows_i, g[0] + 1);
      cols_j = std::max(cols_j, g[1] + 1);
    }
    index.assign(static_cast<size_t>(rows_i) * cols_j, -1);
    for (int k = 0; k < weave.size(); ++k) index[weave.grid[k][0] * cols_j + weave.grid[k][1]] = k;
  }
  int at(int i, int j) const {
    return i < 0 || j < 0 || i >= rows_i || j >= cols_j ? -1 : index[i * cols_j + j];
  }
  // whether the ring at (i, j) has no link to the row before it ((i - 1, j), (i, j + 1)) or none
  // to the row after it ((i + 1, j), (i, j - 1)): the sheet's first or last row
  bool in_end_row(int i, int j) const {
    return (at(i - 1, j) < 0 && at(i, j + 1) < 0) || (at(i + 1, j) < 0 && at(i, j - 1) < 0);
  }
};

}  // namespace

std::vector<DiagonalPair> knight_pairs(const Weave& weave, const WeaveLimits& limits) {
  std::vector<DiagonalPair> pairs;
  if (weave.type != WeaveType::four_in_one) return pairs;
  const GridIndex grid(weave);
  const double far = std::numeric_limits<double>::infinity();
  for (int k = 0; k < weave.size(); ++k) {
    const auto [i, j] = weave.grid[k];
    for (const int other : {grid.at(i + 2, j + 1), grid.at(i + 1, j + 2)}) {
      if (other >= 0) pairs.push_back({std::min(k, other), std::max(k, other), limits.knight, far});
    }
  }
  return pairs;
}

std::vector<DiagonalPair> diagonal_pairs(const Weave& weave, const WeaveLimits& limits) {
  std::vector<DiagonalPair> pairs;
  if (weave.type != WeaveType::four_in_one) return pairs;
  const GridIndex grid(weave);
  for (int k = 0; k < weave.size(); ++k) {
    const auto [i, j] = weave.grid[k];
    const int row = grid.at(i + 1, j + 1), column = grid.at(i + 1, j - 1);
    if (row >= 0) pairs.push_back({std::min(k, row), std::max(k, row), limits.row, limits.row_max});
    if (column >= 0) {
      const bool edge = grid.in_end_row(i, j) || grid.in_end_row(i + 1, j - 1);
      pairs.push_back({std::min(k, column), std::max(k, column),
                       edge ? limits.column_edge : limits.column,
                       std::numeric_limits<double>::infinity()});
    }
  }
  return pairs;
}

}  // namespace chainmail

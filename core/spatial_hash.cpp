#include "core/spatial_hash.hpp"

#include "core/parallel.hpp"

#include <algorithm>
#include <array>
#include <cstddef>

namespace chainmail {

namespace {
constexpr std::int64_t kNotInGrid = -(std::int64_t{1} << 62);  // a point's cell: in none
}  // namespace

// the scratch arrays keep their memory from build to build: a sheet rebuilds its candidate list
// every few substeps, and fresh pages cost more than the sort
void SpatialHash::build(const Positions& points, double cell_size, int table_size, int threads) {
  const int n = static_cast<int>(points.cols());
  inv_cell_ = 1.0 / cell_size;
  const int team = loop_threads(threads, n, 4096);
  std::vector<CellPart> parts(team);
  locate_points(points, team, parts);
  std::int64_t lo[3] = {0, 0, 0}, hi[3] = {-1, -1, -1};
  join_parts(parts, n, team, lo, hi);
  const std::int64_t table = key_points(n, lo, hi, table_size, team);
  sort_by_bucket(points, table, threads);
}

// each part of the points on its own thread: their cells, and the part's box and finite count
// (kept in locals: parts written in the loop would share cache lines between threads)
void SpatialHash::locate_points(const Positions& points, int team, std::vector<CellPart>& parts) {
  const int n = static_cast<int>(points.cols());
  std::vector<std::array<std::int64_t, 3>>& cell = scratch_.cell;
  cell.resize(n);
  parallel_for(0, team, team, [&](int t) {
    const int begin = static_cast<int>(static_cast<long long>(n) * t / team);
    const int end = static_cast<int>(static_cast<long long>(n) * (t + 1) / team);
    std::int64_t lo[3] = {kNotInGrid, kNotInGrid, kNotInGrid};
    std::int64_t hi[3] = {kNotInGrid, kNotInGrid, kNotInGrid};
    int count = 0;
    for (int i = begin; i < end; ++i) {
      const Vec3 p = points.col(i);
      if (!in_grid(p)) {
        cell[i] = {kNotInGrid, 0, 0};
        continue;
      }
      const std::array<std::int64_t, 3> c = {cell_of(p.x()), cell_of(p.y()), cell_of(p.z())};
      cell[i] = c;
      if (count++ == 0) {
        for (int a = 0; a < 3; ++a) lo[a] = hi[a] = c[a];
      }
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], c[a]);
        hi[a] = std::max(hi[a], c[a]);
      }
    }
    CellPart& part = parts[t];
    part.begin = begin;
    part.count = count;
    for (int a = 0; a < 3; ++a) {
      part.lo[a] = lo[a];
      part.hi[a] = hi[a];
    }
  });
}

// the boxes joined, and the finite points listed in index order (each part from its first place)
void SpatialHash::join_parts(std::vector<CellPart>& parts, int n, int team, std::int64_t lo[3],
                             std::int64_t hi[3]) {
  int finite_count = 0;
  for (CellPart& part : parts) {
    if (part.count == 0) continue;
    for (int a = 0; a < 3; ++a) {
      lo[a] = finite_count == 0 ? part.lo[a] : std::min(lo[a], part.lo[a]);
      hi[a] = finite_count == 0 ? part.hi[a] : std::max(hi[a], part.hi[a]);
    }
    const int first = finite_count;
    finite_count += part.count;
    part.count = first;  // now the part's first place in the finite list
  }
  std::vector<int>& finite = scratch_.finite;
  const std::vector<std::array<std::int64_t, 3>>& cell = scratch_.cell;
  finite.resize(finite_count);
  if (finite_count == n) {
    for (int i = 0; i < n; ++i) finite[i] = i;
    return;
  }
  parallel_for(0, team, team, [&](int t) {
    const int end = t + 1 < team ? parts[t + 1].begin : n;
    int at = parts[t].count;
    for (int i = parts[t].begin; i < end; ++i) {
      if (cell[i][0] != kNotInGrid) finite[at++] = i;
    }
  });
}

// dense when the box holds at most 32 cells per point, or at most 4096 cells in all (small sets)
std::int64_t SpatialHash::key_points(int n, const std::int64_t lo[3], const std::int64_t hi[3],
                                     int table_size, int team) {
  const std::vector<int>& finite = scratch_.finite;
  const std::vector<std::array<std::int64_t, 3>>& cell = scratch_.cell;
  std::int64_t cells = 1;
  for (int a = 0; a < 3; ++a) {
    origin_[a] = lo[a];
    dims_[a] = std::max<std::int64_t>(hi[a] - lo[a] + 1, 1);
    cells = std::min<std::int64_t>(cells * dims_[a], std::int64_t{1} << 40);
  }
  dense_ =
      !finite.empty() && cells <= std::max<std::int64_t>(32 * static_cast<std::int64_t>(n), 4096);

  std::int64_t table = 0;
  std::vector<std::uint64_t>& key_of = scratch_.key;
  std::vector<int>& bucket_of = scratch_.bucket;
  key_of.resize(n);
  bucket_of.resize(n);
  const int count = static_cast<int>(finite.size());
  if (dense_) {
    table = cells;
    parallel_for(0, count, team, [&](int k) {
      const int i = finite[k];
      key_of[i] = static_cast<std::uint64_t>(
          dense_index(cell[i][0] - lo[0], cell[i][1] - lo[1], cell[i][2] - lo[2]));
      bucket_of[i] = static_cast<int>(key_of[i]);
    });
  } else {
    table = 64;
    while (table < (table_size > 0 ? table_size : 2 * n)) table *= 2;
    mask_ = static_cast<std::uint64_t>(table - 1);
    parallel_for(0, count, team, [&](int k) {
      const int i = finite[k];
      key_of[i] = pack_cell(cell[i][0], cell[i][1], cell[i][2]);
      bucket_of[i] = bucket_of_key(key_of[i]);
    });
  }
  return table;
}

// counting sort by bucket, stable (ascending index within a bucket) for any thread count: each
// part of the finite points, in index order, counts its points per bucket into a histogram of
// its own; the histograms are summed bucket by bucket, part after part, into each part's first
// slot in every bucket; each part then places its points in index order. A histogram spans the
// table, so the parts run on more than one thread only while the table is small beside the
// points (a sheet's grid is)
void SpatialHash::sort_by_bucket(const Positions& points, std::int64_t table, int threads) {
  const std::vector<int>& finite = scratch_.finite;
  const std::vector<std::uint64_t>& key_of = scratch_.key;
  const std::vector<int>& bucket_of = scratch_.bucket;
  const int count = static_cast<int>(finite.size());
  bucket_start_.resize(static_cast<size_t>(table) + 1);
  sorted_.resize(count);
  sorted_key_.resize(count);
  sorted_position_.resize(3, count);
  const int sorters =
      table <= 4 * static_cast<std::int64_t>(count) ? loop_threads(threads, count, 4096) : 1;
  std::vector<int>& fill = scratch_.fill;  // (sorters, table) row by row
  fill.resize(static_cast<size_t>(table) * sorters);
  auto part_begin = [&](int t) {
    return static_cast<int>(static_cast<long long>(count) * t / sorters);
  };
  parallel_for(0, sorters, sorters, [&](int t) {
    int* const own = fill.data() + static_cast<std::ptrdiff_t>(t) * table;
    std::fill(own, own + table, 0);
    for (int k = part_begin(t); k < part_begin(t + 1); ++k) ++own[bucket_of[finite[k]]];
  });
  int total = 0;
  for (std::int64_t b = 0; b < table; ++b) {
    bucket_start_[b] = total;
    for (int t = 0; t < sorters; ++t) {
      int& slot = fill[static_cast<std::ptrdiff_t>(t) * table + b];
      const int here = slot;
      slot = total;
      total += here;
    }
  }
  bucket_start_[table] = count;
  parallel_for(0, sorters, sorters, [&](int t) {
    int* const own = fill.data() + static_cast<std::ptrdiff_t>(t) * table;
    for (int k = part_begin(t); k < part_begin(t + 1); ++k) {
      const int i = finite[k];
      const int slot = own[bucket_of[i]]++;
      sorted_[slot] = i;
      sorted_key_[slot] = key_of[i];
      sorted_position_.col(slot) = points.col(i);
    }
  });
}

long long SpatialHash::foreign_entries() const {
  long long foreign = 0;
  for (int b = 0; b + 1 < static_cast<int>(bucket_start_.size()); ++b) {
    for (int k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k) {
      foreign += sorted_key_[k] != sorted_key_[bucket_start_[b]];
    }
  }
  return foreign;
}

}  // namespace chainmail

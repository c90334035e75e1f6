#include "core/spatial_hash.hpp"

#include "core/parallel.hpp"

#include <algorithm>
#include <array>

namespace chainmail {

void SpatialHash::build(const Positions& points, double cell_size, int table_size, int threads) {
  const int n = static_cast<int>(points.cols());
  inv_cell_ = 1.0 / cell_size;

  // cell coordinates of every finite point, and their extent
  // (the scratch arrays keep their memory from build to build: a sheet rebuilds its candidate
  // list every few substeps, and fresh pages cost more than the sort)
  std::vector<int>& finite = scratch_.finite;
  finite.clear();
  finite.reserve(n);
  std::vector<std::array<std::int64_t, 3>>& cell = scratch_.cell;
  cell.resize(n);
  // the cells per point on the threads (independent), the box and the finite list after
  constexpr std::int64_t kNone = -(std::int64_t{1} << 62);  // not in the grid
  const int team = loop_threads(threads, n, 4096);
#pragma omp parallel for schedule(static) num_threads(team)
  for (int i = 0; i < n; ++i) {
    const Vec3 p = points.col(i);
    cell[i] = in_grid(p)
                  ? std::array<std::int64_t, 3>{cell_of(p.x()), cell_of(p.y()), cell_of(p.z())}
                  : std::array<std::int64_t, 3>{kNone, 0, 0};
  }
  // the box, and the finite points in index order: each part of the points on its own thread,
  // the parts' boxes and lists joined in order after
  std::int64_t lo[3] = {0, 0, 0}, hi[3] = {-1, -1, -1};
  struct Part {
    std::int64_t lo[3], hi[3];
    int begin = 0, count = 0;  // points, and finite points among them
  };
  std::vector<Part> parts(team);
#pragma omp parallel for schedule(static) num_threads(team)
  for (int t = 0; t < team; ++t) {
    Part& part = parts[t];
    part.begin = static_cast<int>(static_cast<long long>(n) * t / team);
    const int end = static_cast<int>(static_cast<long long>(n) * (t + 1) / team);
    for (int i = part.begin; i < end; ++i) {
      if (cell[i][0] == kNone) continue;
      for (int a = 0; a < 3; ++a) {
        part.lo[a] = part.count == 0 ? cell[i][a] : std::min(part.lo[a], cell[i][a]);
        part.hi[a] = part.count == 0 ? cell[i][a] : std::max(part.hi[a], cell[i][a]);
      }
      ++part.count;
    }
  }
  int finite_count = 0;
  for (Part& part : parts) {
    if (part.count == 0) continue;
    for (int a = 0; a < 3; ++a) {
      lo[a] = finite_count == 0 ? part.lo[a] : std::min(lo[a], part.lo[a]);
      hi[a] = finite_count == 0 ? part.hi[a] : std::max(hi[a], part.hi[a]);
    }
    const int first = finite_count;
    finite_count += part.count;
    part.count = first;  // now the part's first place in the finite list
  }
  finite.resize(finite_count);
#pragma omp parallel for schedule(static) num_threads(team)
  for (int t = 0; t < team; ++t) {
    const int end = t + 1 < team ? parts[t + 1].begin : n;
    int at = parts[t].count;
    for (int i = parts[t].begin; i < end; ++i) {
      if (cell[i][0] != kNone) finite[at++] = i;
    }
  }

  // dense when the box holds at most 32 cells per point, or at most 4096 cells in all (small sets)
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
#pragma omp parallel for schedule(static) num_threads(team)
    for (int k = 0; k < count; ++k) {
      const int i = finite[k];
      key_of[i] = static_cast<std::uint64_t>(
          dense_index(cell[i][0] - lo[0], cell[i][1] - lo[1], cell[i][2] - lo[2]));
      bucket_of[i] = static_cast<int>(key_of[i]);
    }
  } else {
    table = 64;
    while (table < (table_size > 0 ? table_size : 2 * n)) table *= 2;
    mask_ = static_cast<std::uint64_t>(table - 1);
#pragma omp parallel for schedule(static) num_threads(team)
    for (int k = 0; k < count; ++k) {
      const int i = finite[k];
      key_of[i] = pack_cell(cell[i][0], cell[i][1], cell[i][2]);
      bucket_of[i] = bucket_of_key(key_of[i]);
    }
  }

  // counting sort by bucket: count, prefix sum, scatter (stable: ascending index within a bucket).
  // Each thread takes a range of buckets and the points that fall in it, so every bucket's points
  // are placed by one thread in index order: the same layout for any thread count
  bucket_start_.resize(static_cast<size_t>(table) + 1);
  std::vector<int>& fill = scratch_.fill;
  fill.resize(static_cast<size_t>(table));
  sorted_.resize(count);
  sorted_key_.resize(count);
  sorted_position_.resize(3, count);
  const int sorters = loop_threads(threads, std::min<std::int64_t>(count, table), 4096);
  std::vector<int> range_total(sorters + 1, 0);  // (sorters + 1) points before each range
#pragma omp parallel num_threads(sorters)
  {
    int t = 0, members = 1;
#if defined(CHAINMAIL_HAS_OPENMP)
    t = omp_get_thread_num();
    members = omp_get_num_threads();
#endif
    const std::int64_t first = table * t / members, last = table * (t + 1) / members;
    // count the range's points into fill, then sum them up in place
    std::fill(fill.begin() + first, fill.begin() + last, 0);
    for (int i : finite) {
      const int b = bucket_of[i];
      if (b >= first && b < last) ++fill[b];
    }
    int total = 0;
    for (std::int64_t b = first; b < last; ++b) {
      const int here = fill[b];
      fill[b] = total;
      total += here;
    }
    range_total[t + 1] = total;
#pragma omp barrier
    int offset = 0;  // points in the ranges before this one
    for (int r = 0; r <= t; ++r) offset += range_total[r];
    for (std::int64_t b = first; b < last; ++b) {
      fill[b] += offset;
      bucket_start_[b] = fill[b];
    }
    if (t + 1 == members) bucket_start_[table] = count;
    for (int i : finite) {
      const int b = bucket_of[i];
      if (b < first || b >= last) continue;
      const int slot = fill[b]++;
      sorted_[slot] = i;
      sorted_key_[slot] = key_of[i];
      sorted_position_.col(slot) = points.col(i);
    }
  }
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

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
  std::int64_t lo[3] = {0, 0, 0}, hi[3] = {-1, -1, -1};
  for (int i = 0; i < n; ++i) {
    if (cell[i][0] == kNone) continue;
    for (int a = 0; a < 3; ++a) {
      lo[a] = finite.empty() ? cell[i][a] : std::min(lo[a], cell[i][a]);
      hi[a] = finite.empty() ? cell[i][a] : std::max(hi[a], cell[i][a]);
    }
    finite.push_back(i);
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

  // counting sort by bucket: count, prefix sum, scatter (stable: ascending index within a bucket)
  bucket_start_.assign(static_cast<size_t>(table) + 1, 0);
  for (int i : finite) ++bucket_start_[bucket_of[i] + 1];
  for (std::int64_t b = 0; b < table; ++b) bucket_start_[b + 1] += bucket_start_[b];
  std::vector<int>& fill = scratch_.fill;
  fill.assign(bucket_start_.begin(), bucket_start_.end() - 1);
  sorted_.resize(count);
  sorted_key_.resize(count);
  sorted_position_.resize(3, count);
  for (int i : finite) {
    const int slot = fill[bucket_of[i]]++;
    sorted_[slot] = i;
    sorted_key_[slot] = key_of[i];
    sorted_position_.col(slot) = points.col(i);
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

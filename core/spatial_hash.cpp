#include "core/spatial_hash.hpp"

#include <algorithm>

namespace chainmail {

std::uint64_t hash_cell(std::int64_t x, std::int64_t y, std::int64_t z) {
  // pack 21 bits per axis, then the splitmix64 finaliser spreads every input bit over the output
  std::uint64_t key = (static_cast<std::uint64_t>(x) & 0x1fffff) |
                      ((static_cast<std::uint64_t>(y) & 0x1fffff) << 21) |
                      ((static_cast<std::uint64_t>(z) & 0x1fffff) << 42);
  key ^= key >> 30;
  key *= 0xbf58476d1ce4e5b9ull;
  key ^= key >> 27;
  key *= 0x94d049bb133111ebull;
  key ^= key >> 31;
  return key;
}

void SpatialHash::build(const Positions& points, double cell_size, int table_size) {
  const int n = static_cast<int>(points.cols());
  inv_cell_ = 1.0 / cell_size;
  const int table = table_size > 0 ? table_size : std::max(64, 2 * n + 1);
  bucket_start_.assign(table + 1, 0);
  sorted_.resize(n);
  // counting sort by bucket: count, prefix sum, scatter
  std::vector<int> bucket_of(n);
  for (int i = 0; i < n; ++i) {
    const Vec3 p = points.col(i);
    bucket_of[i] = bucket(cell_of(p.x()), cell_of(p.y()), cell_of(p.z()));
    ++bucket_start_[bucket_of[i] + 1];
  }
  for (int b = 0; b < table; ++b) bucket_start_[b + 1] += bucket_start_[b];
  std::vector<int> fill(bucket_start_.begin(), bucket_start_.end() - 1);
  for (int i = 0; i < n; ++i) sorted_[fill[bucket_of[i]]++] = i;
}

long long SpatialHash::foreign_entries(const Positions& points) const {
  long long foreign = 0;
  for (int b = 0; b + 1 < static_cast<int>(bucket_start_.size()); ++b) {
    for (int k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k) {
      const Vec3 p = points.col(sorted_[k]);
      const Vec3 q = points.col(sorted_[bucket_start_[b]]);
      const bool same_cell = cell_of(p.x()) == cell_of(q.x()) && cell_of(p.y()) == cell_of(q.y()) &&
                             cell_of(p.z()) == cell_of(q.z());
      foreign += !same_cell;
    }
  }
  return foreign;
}

}  // namespace chainmail

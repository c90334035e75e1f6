#include "core/spatial_hash.hpp"

#include <algorithm>

namespace chainmail {

void SpatialHash::build(const Positions& points, double cell_size, int table_size) {
  const int n = static_cast<int>(points.cols());
  inv_cell_ = 1.0 / cell_size;
  int table = 64;
  while (table < (table_size > 0 ? table_size : 2 * n)) table *= 2;
  mask_ = static_cast<std::uint64_t>(table - 1);
  bucket_start_.assign(table + 1, 0);
  sorted_.resize(n);
  // counting sort by bucket: count, prefix sum, scatter
  std::vector<int> bucket_of(n);
  std::vector<std::uint64_t> key_of(n);
  for (int i = 0; i < n; ++i) {
    const Vec3 p = points.col(i);
    key_of[i] = pack_cell(cell_of(p.x()), cell_of(p.y()), cell_of(p.z()));
    bucket_of[i] = bucket_of_key(key_of[i]);
    ++bucket_start_[bucket_of[i] + 1];
  }
  for (int b = 0; b < table; ++b) bucket_start_[b + 1] += bucket_start_[b];
  std::vector<int> fill(bucket_start_.begin(), bucket_start_.end() - 1);
  sorted_key_.resize(n);
  for (int i = 0; i < n; ++i) {
    const int slot = fill[bucket_of[i]]++;
    sorted_[slot] = i;
    sorted_key_[slot] = key_of[i];
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

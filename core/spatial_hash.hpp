// Uniform-grid spatial hash for "who is near whom" queries (repulsion, self-collision, metrics).
// Cells are hashed with a well-mixed 64-bit mix of the integer coordinates, not x + y^2 + z^3,
// and points are counting-sorted into the table so a query touches contiguous memory.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/types.hpp"

namespace chainmail {

// a well-mixed hash of integer cell coordinates (splitmix64 finaliser over a packed key)
std::uint64_t hash_cell(std::int64_t x, std::int64_t y, std::int64_t z);

class SpatialHash {
 public:
  // cell_size should be at least the query radius; table_size 0 picks ~2x the point count
  void build(const Positions& points, double cell_size, int table_size = 0);

  // calls visit(j) for every point j > i (or every j != i when all_pairs) within `radius` of point i
  template <class Visit>
  void for_each_near(const Positions& points, int i, double radius, Visit&& visit) const;
  // every unordered pair (i < j) closer than `radius`; radius <= cell size
  template <class Visit>
  void for_each_pair(const Positions& points, double radius, Visit&& visit) const;

  int table_size() const { return static_cast<int>(bucket_start_.size()) - 1; }
  // number of points sharing a bucket with a point of another cell (hash collisions), for tests
  long long foreign_entries(const Positions& points) const;

 private:
  std::int64_t cell_of(double x) const { return static_cast<std::int64_t>(std::floor(x * inv_cell_)); }
  int bucket(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return static_cast<int>(hash_cell(x, y, z) % static_cast<std::uint64_t>(table_size()));
  }

  double inv_cell_ = 1.0;
  std::vector<int> bucket_start_;  // (table + 1) prefix offsets into sorted_
  std::vector<int> sorted_;        // (n) point indices grouped by bucket
};

template <class Visit>
void SpatialHash::for_each_near(const Positions& points, int i, double radius, Visit&& visit) const {
  const Vec3 p = points.col(i);
  const double r2 = radius * radius;
  const std::int64_t cx = cell_of(p.x()), cy = cell_of(p.y()), cz = cell_of(p.z());
  // the 27 cells around p; distinct cells may share a bucket, so visit each bucket once
  int seen[27];
  int seen_count = 0;
  for (std::int64_t dx = -1; dx <= 1; ++dx) {
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      for (std::int64_t dz = -1; dz <= 1; ++dz) {
        const int b = bucket(cx + dx, cy + dy, cz + dz);
        bool repeat = false;
        for (int s = 0; s < seen_count; ++s) repeat |= seen[s] == b;
        if (repeat) continue;
        seen[seen_count++] = b;
        for (int k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k) {
          const int j = sorted_[k];
          if (j <= i) continue;
          if ((points.col(j) - p).squaredNorm() < r2) visit(j);
        }
      }
    }
  }
}

template <class Visit>
void SpatialHash::for_each_pair(const Positions& points, double radius, Visit&& visit) const {
  for (int i = 0; i < points.cols(); ++i) {
    for_each_near(points, i, radius, [&](int j) { visit(i, j); });
  }
}

}  // namespace chainmail

// Uniform-grid spatial hash for "who is near whom" queries (repulsion, self-collision, metrics).
// Cells are hashed with a well-mixed 64-bit mix of the integer coordinates, not x + y^2 + z^3,
// and points are counting-sorted into the table so a query touches contiguous memory.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/types.hpp"

namespace chainmail {

// integer cell coordinates packed 21 bits per axis
inline std::uint64_t pack_cell(std::int64_t x, std::int64_t y, std::int64_t z) {
  return (static_cast<std::uint64_t>(x) & 0x1fffff) |
         ((static_cast<std::uint64_t>(y) & 0x1fffff) << 21) |
         ((static_cast<std::uint64_t>(z) & 0x1fffff) << 42);
}
// a well-mixed hash of a packed cell key (the splitmix64 finaliser)
inline std::uint64_t mix_cell(std::uint64_t key) {
  key ^= key >> 30;
  key *= 0xbf58476d1ce4e5b9ull;
  key ^= key >> 27;
  key *= 0x94d049bb133111ebull;
  key ^= key >> 31;
  return key;
}
inline std::uint64_t hash_cell(std::int64_t x, std::int64_t y, std::int64_t z) {
  return mix_cell(pack_cell(x, y, z));
}

class SpatialHash {
 public:
  // cell_size should be at least the query radius; the table has a power-of-two size of at least
  // table_size buckets (0: twice the point count)
  void build(const Positions& points, double cell_size, int table_size = 0);

  // calls visit(j) for every point j > i (or every j != i when all_pairs) within `radius` of point
  // i
  template <class Visit>
  void for_each_near(const Positions& points, int i, double radius, Visit&& visit) const;
  // every unordered pair (i < j) closer than `radius`; radius <= cell size
  template <class Visit>
  void for_each_pair(const Positions& points, double radius, Visit&& visit) const;

  int table_size() const { return static_cast<int>(bucket_start_.size()) - 1; }
  // number of points sharing a bucket with a point of another cell (hash collisions), for tests
  long long foreign_entries() const;

 private:
  std::int64_t cell_of(double x) const {
    return static_cast<std::int64_t>(std::floor(x * inv_cell_));
  }
  int bucket_of_key(std::uint64_t key) const {
    return static_cast<int>(mix_cell(key) & mask_);  // power-of-two table
  }

  double inv_cell_ = 1.0;
  std::uint64_t mask_ = 0;
  std::vector<int> bucket_start_;          // (table + 1) prefix offsets into sorted_
  std::vector<int> sorted_;                // (n) point indices grouped by bucket
  std::vector<std::uint64_t> sorted_key_;  // (n) packed cell of each sorted point
};

template <class Visit>
void SpatialHash::for_each_near(const Positions& points, int i, double radius,
                                Visit&& visit) const {
  const Vec3 p = points.col(i);
  const double r2 = radius * radius;
  const std::int64_t cx = cell_of(p.x()), cy = cell_of(p.y()), cz = cell_of(p.z());
  // the 27 cells around p; a bucket may hold points of other cells (hash collisions): skip them
  for (std::int64_t dx = -1; dx <= 1; ++dx) {
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      for (std::int64_t dz = -1; dz <= 1; ++dz) {
        const std::uint64_t key = pack_cell(cx + dx, cy + dy, cz + dz);
        const int b = bucket_of_key(key);
        for (int k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k) {
          const int j = sorted_[k];
          if (j <= i || sorted_key_[k] != key) continue;
          if ((points.col(j) - p).squaredNorm() < r2) visit(j);
        }
      }
    }
  }
}

template <class Visit>
void SpatialHash::for_each_pair(const Positions& points, double radius, Visit&& visit) const {
  // half shell: each point looks at later points of its own cell and every point of the 13 cells
  // lexicographically after its own, so each pair is met exactly once
  const double r2 = radius * radius;
  for (int i = 0; i < points.cols(); ++i) {
    const Vec3 p = points.col(i);
    const std::int64_t cx = cell_of(p.x()), cy = cell_of(p.y()), cz = cell_of(p.z());
    for (std::int64_t dx = 0; dx <= 1; ++dx) {
      for (std::int64_t dy = dx == 0 ? 0 : -1; dy <= 1; ++dy) {
        for (std::int64_t dz = (dx == 0 && dy == 0) ? 0 : -1; dz <= 1; ++dz) {
          const bool own = dx == 0 && dy == 0 && dz == 0;
          const std::uint64_t key = pack_cell(cx + dx, cy + dy, cz + dz);
          const int b = bucket_of_key(key);
          for (int k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k) {
            const int j = sorted_[k];
            if (sorted_key_[k] != key || (own && j <= i)) continue;
            if ((points.col(j) - p).squaredNorm() < r2) visit(std::min(i, j), std::max(i, j));
          }
        }
      }
    }
  }
}

}  // namespace chainmail

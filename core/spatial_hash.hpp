// Uniform-grid spatial hash for "who is near whom" queries (repulsion, self-collision, metrics).
// Cells are hashed with a well-mixed 64-bit mix of the integer coordinates, not x + y^2 + z^3,
// and points are counting-sorted into the table so a query touches contiguous memory.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/parallel.hpp"
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

// Two layouts behind one interface, chosen per build from the points' extent:
//  - dense: when the bounding box holds at most 32 cells per point, or at most 4096 cells in all
//    (a sheet, a pile, a small set), cells are a plain 3-D array with z fastest, so the three
//    cells along z of a neighbourhood row are one contiguous run of sorted points: a half-shell
//    query reads 5 runs instead of 14 cells;
//  - hashed: otherwise (points spread far apart), cells go through mix_cell into a power-of-two
//    table and every candidate is checked against its packed cell key (hash collisions).
// Non-finite points are in no cell: they are never visited and never visit.
class SpatialHash {
 public:
  // cell_size should be at least the query radius; the hashed table has a power-of-two size of
  // at least table_size buckets (0: twice the point count), and never fewer than 64
  // (threads: for the per-point loops; the result is the same for any count)
  void build(const Positions& points, double cell_size, int table_size = 0, int threads = 1);

  // calls visit(j) for every point j > i within `radius` of point i (radius <= cell size), so
  // that calling it for every i meets each pair once
  template <class Visit>
  void for_each_near(const Positions& points, int i, double radius, Visit&& visit) const;
  // every unordered pair (i < j) closer than `radius`, each once; radius <= cell size
  template <class Visit>
  void for_each_pair(const Positions& points, double radius, Visit&& visit) const {
    for_each_pair_in(points, radius, 0, pair_walk_size(points), visit);
  }
  // the same walk in parts: for_each_pair is for_each_pair_in over [0, pair_walk_size) and the
  // parts of any split, run one after the other, meet the pairs in the same order (so threads may
  // each walk a part into its own list, and the lists joined in order equal the whole walk)
  int pair_walk_size(const Positions& points) const {
    return dense_ ? static_cast<int>(sorted_.size()) : static_cast<int>(points.cols());
  }
  template <class Visit>
  void for_each_pair_in(const Positions& points, double radius, int begin, int end,
                        Visit&& visit) const;

  bool dense() const { return dense_; }
  int table_size() const { return static_cast<int>(bucket_start_.size()) - 1; }
  // number of points sharing a bucket with a point of another cell (hash collisions), for tests
  long long foreign_entries() const;

 private:
  // floor(x / cell) for a coordinate within the grid (in_grid: at most 2^20 cells out), without
  // the library call std::floor is on a build for the baseline instruction set
  std::int64_t cell_of(double x) const {
    const double s = x * inv_cell_;
    const auto toward_zero = static_cast<std::int64_t>(s);
    return toward_zero - (s < static_cast<double>(toward_zero));
  }
  // finite and within the 2^20 cells a packed key holds per axis; other points are in no cell
  bool in_grid(const Vec3& p) const {
    return p.allFinite() && p.cwiseAbs().maxCoeff() * inv_cell_ <= 1e6;
  }
  int bucket_of_key(std::uint64_t key) const {
    return static_cast<int>(mix_cell(key) & mask_);  // power-of-two table
  }
  // dense layout: index of cell (x, y, z) relative to the grid origin, all in range
  std::int64_t dense_index(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return (x * dims_[1] + y) * dims_[2] + z;
  }
  // calls visit(slot) for the sorted slots of cells (x, y, z_lo..z_hi), clipped to the grid
  template <class Visit>
  void for_each_in_run(std::int64_t x, std::int64_t y, std::int64_t z_lo, std::int64_t z_hi,
                       Visit&& visit) const {
    int first = 0, last = 0;
    if (!run_slots(x, y, z_lo, z_hi, first, last)) return;
    for (int slot = first; slot < last; ++slot) visit(slot);
  }
  // the sorted slots [first, last) of cells (x, y, z_lo..z_hi), clipped to the grid; false when
  // the run is outside it
  bool run_slots(std::int64_t x, std::int64_t y, std::int64_t z_lo, std::int64_t z_hi, int& first,
                 int& last) const {
    if (x < 0 || x >= dims_[0] || y < 0 || y >= dims_[1]) return false;
    z_lo = std::max<std::int64_t>(z_lo, 0);
    z_hi = std::min<std::int64_t>(z_hi, dims_[2] - 1);
    if (z_lo > z_hi) return false;
    first = bucket_start_[dense_index(x, y, z_lo)];
    last = bucket_start_[dense_index(x, y, z_hi) + 1];
    return true;
  }

  // build()'s steps, in order. A part of the points, located on a thread of its own (alignas:
  // parts written side by side would share cache lines between threads)
  struct alignas(kCacheLine) CellPart {
    std::int64_t lo[3], hi[3];  // the box of its finite points' cells
    int begin = 0, count = 0;   // its first point, and its finite points (after join_parts: its
                                // first place in the finite list)
  };
  // every point's cell (kNotInGrid: none), each part's box and finite count
  void locate_points(const Positions& points, int team, std::vector<CellPart>& parts);
  // the parts' boxes joined into lo..hi (empty: lo > hi) and the finite points listed in order
  void join_parts(std::vector<CellPart>& parts, int n, int team, std::int64_t lo[3],
                  std::int64_t hi[3]);
  // the layout (dense or hashed) over the box, and every finite point's key and bucket; returns
  // the number of buckets
  std::int64_t key_points(int n, const std::int64_t lo[3], const std::int64_t hi[3], int table_size,
                          int team);
  // the finite points sorted by bucket into sorted_, stably, with their keys and positions
  void sort_by_bucket(const Positions& points, std::int64_t table, int threads);

  double inv_cell_ = 1.0;
  bool dense_ = false;
  std::int64_t origin_[3] = {0, 0, 0};     // dense: cell coordinates of the grid's first cell
  std::int64_t dims_[3] = {0, 0, 0};       // dense: cells per axis
  std::uint64_t mask_ = 0;                 // hashed: table size - 1
  std::vector<int> bucket_start_;          // (cells or table + 1) prefix offsets into sorted_
  std::vector<int> sorted_;                // (finite points) point indices grouped by cell/bucket
  std::vector<std::uint64_t> sorted_key_;  // (finite points) packed cell (hashed) or cell index
  Positions sorted_position_;              // (3, finite points) m, positions in sorted order
  struct Scratch {
    std::vector<int> finite;                        // (finite points) point indices
    std::vector<std::array<std::int64_t, 3>> cell;  // (n) cell coordinates
    std::vector<std::uint64_t> key;                 // (n) packed cell or cell index
    std::vector<int> bucket;                        // (n)
    std::vector<int> fill;                          // (buckets) next free slot
  } scratch_;                                       // build()'s working memory, reused
};

template <class Visit>
void SpatialHash::for_each_near(const Positions& points, int i, double radius,
                                Visit&& visit) const {
  const Vec3 p = points.col(i);
  if (!in_grid(p)) return;
  const double r2 = radius * radius;
  const std::int64_t cx = cell_of(p.x()), cy = cell_of(p.y()), cz = cell_of(p.z());
  if (dense_) {
    // 9 runs of 3 cells along z
    const std::int64_t x = cx - origin_[0], y = cy - origin_[1], z = cz - origin_[2];
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        for_each_in_run(x + dx, y + dy, z - 1, z + 1, [&](int slot) {
          const int j = sorted_[slot];
          if (j > i && (sorted_position_.col(slot) - p).squaredNorm() < r2) visit(j);
        });
      }
    }
    return;
  }
  // the 27 cells around p; a bucket may hold points of other cells (hash collisions): skip them
  for (std::int64_t dx = -1; dx <= 1; ++dx) {
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      for (std::int64_t dz = -1; dz <= 1; ++dz) {
        const std::uint64_t key = pack_cell(cx + dx, cy + dy, cz + dz);
        const int b = bucket_of_key(key);
        for (int k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k) {
          const int j = sorted_[k];
          if (j <= i || sorted_key_[k] != key) continue;
          if ((sorted_position_.col(k) - p).squaredNorm() < r2) visit(j);
        }
      }
    }
  }
}

template <class Visit>
void SpatialHash::for_each_pair_in(const Positions& points, double radius, int begin, int end,
                                   Visit&& visit) const {
  // half shell: each point looks at later points of its own cell and every point of the 13 cells
  // lexicographically after its own, so each pair is met exactly once
  const double r2 = radius * radius;
  if (dense_) {
    // walk the points in cell order; the half shell is the rest of the own cell and the next z
    // cell, then the runs of 3 cells along z in the rows (0, +1) and (+1, -1..+1). The runs
    // follow from the cell alone, so they are found once per cell (a cell holds a few points),
    // and runs that continue each other in the sorted order are read as one (a sheet one cell
    // thick puts the three rows of x + 1 side by side): the same slots in the same order
    std::int64_t cached = -1;
    int own_end = 0, runs = 0;
    int run_first[4], run_last[4];
    for (int s = begin; s < end; ++s) {
      const auto cell = static_cast<std::int64_t>(sorted_key_[s]);
      if (cell != cached) {
        cached = cell;
        const std::int64_t z = cell % dims_[2], y = (cell / dims_[2]) % dims_[1],
                           x = cell / (dims_[2] * dims_[1]);
        own_end = bucket_start_[cell + (z + 1 < dims_[2] ? 2 : 1)];
        runs = 0;
        auto add_run = [&](std::int64_t rx, std::int64_t ry) {
          int first = 0, last = 0;
          if (!run_slots(rx, ry, z - 1, z + 1, first, last)) return;
          if (runs > 0 && run_last[runs - 1] == first) {
            run_last[runs - 1] = last;
          } else {
            run_first[runs] = first;
            run_last[runs++] = last;
          }
        };
        add_run(x, y + 1);
        for (std::int64_t dy = -1; dy <= 1; ++dy) add_run(x + 1, y + dy);
      }
      const int i = sorted_[s];
      const double px = sorted_position_(0, s), py = sorted_position_(1, s),
                   pz = sorted_position_(2, s);
      auto near = [&](int first, int last) {
        for (int slot = first; slot < last; ++slot) {
          const double dx = sorted_position_(0, slot) - px, dy = sorted_position_(1, slot) - py,
                       dz = sorted_position_(2, slot) - pz;
          if (dx * dx + dy * dy + dz * dz < r2) {
            const int j = sorted_[slot];
            visit(std::min(i, j), std::max(i, j));
          }
        }
      };
      near(s + 1, own_end);
      for (int r = 0; r < runs; ++r) near(run_first[r], run_last[r]);
    }
    return;
  }
  for (int i = begin; i < end; ++i) {
    const Vec3 p = points.col(i);
    if (!in_grid(p)) continue;
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
            if ((sorted_position_.col(k) - p).squaredNorm() < r2)
              visit(std::min(i, j), std::max(i, j));
          }
        }
      }
    }
  }
}

}  // namespace chainmail

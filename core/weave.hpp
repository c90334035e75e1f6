// Weave generators: the fixed topology of the fabric and its rest layout.
// European 4-in-1: rings sit in physical rows; row r leans by +tilt, row r+1 by -tilt, and each
// ring passes through two rings of the row above and two of the row below. Those four are its grid
// neighbours (i +- 1, j), (i, j +- 1) with i = col + ceil(row / 2), j = col - floor(row / 2) +
// offset. Chain (2-in-1): ring k linked to k +- 1, alternate rings turned a quarter turn about the
// chain. Grid: a square grid of point masses at a given spacing (cloth scenes); (i, j) = (col,
// row).
#pragma once

#include <array>
#include <vector>

#include "core/scene.hpp"
#include "core/types.hpp"

namespace chainmail {

struct Weave {
  WeaveType type = WeaveType::four_in_one;
  int rows = 0, cols = 0;
  std::vector<std::array<int, 2>> grid;     // (n) grid index (i, j)
  std::vector<std::array<int, 2>> row_col;  // (n) physical (row, col)
  std::vector<std::array<int, 4>>
      neighbours;                 // (n) ring of (i-1,j), (i+1,j), (i,j-1), (i,j+1); -1 none
  std::vector<RingPair> links;    // (m) linked neighbour pairs, a < b
  std::vector<int> parity;        // (n) +1 / -1: lean / quarter-turn sign
  Positions rest_position;        // (3, n) m
  Orientations rest_orientation;  // (4, n) w, x, y, z
  Vec3 row_axis, advance_axis, normal_axis;  // unit; sheet frame of the rest layout

  int size() const { return static_cast<int>(grid.size()); }
  int ring_at_row_col(int row, int col) const;  // -1 when absent
};

// rest lean of 4-in-1 rows and the row geometry, as fractions of the inner diameter
inline constexpr double kFourInOneTiltRad = 0.6108652381980153;  // 35 degrees
inline constexpr double kFourInOneRowSpacing = 0.8;              // in-row centre distance / ID
inline constexpr double kFourInOneRowAdvance = 0.8;  // distance between adjacent rows / ID
// smallest aspect ratio for which the generator's layout interlocks without interpenetration
inline constexpr double kFourInOneMinAspectRatio = 3.5;
inline constexpr double kChainMinAspectRatio = 2.0;

Weave make_weave(const WeaveSpec& spec, const RingGeometry& ring);
// ring indices pinned by the scene (sorted, unique); throws SceneError for rings that do not exist
std::vector<int> resolve_pins(const Scene& scene, const Weave& weave);
// mass of every ring: the ring mass times any load's factor, kg
std::vector<double> ring_masses(const Scene& scene, const Weave& weave);

}  // namespace chainmail

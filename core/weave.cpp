#include "core/weave.hpp"

#include <algorithm>
#include <numbers>
#include <string>

namespace chainmail {
namespace {

struct SheetAxes {
  Vec3 row, advance, normal;
};

// rows run along `row`, rows advance along `advance`; normal = advance x row so that the local
// ring frame (X = row, Y = normal, Z = advance) is right-handed
SheetAxes sheet_axes(SheetPlane plane) {
  switch (plane) {
    case SheetPlane::xz:
      return {Vec3::UnitX(), Vec3::UnitZ(), Vec3::UnitY()};
    case SheetPlane::xy:
      return {Vec3::UnitX(), -Vec3::UnitY(), Vec3::UnitZ()};
    case SheetPlane::yz:
      return {Vec3::UnitZ(), -Vec3::UnitY(), -Vec3::UnitX()};
    case SheetPlane::yx:
      return {-Vec3::UnitY(), Vec3::UnitX(), -Vec3::UnitZ()};
  }
  return {Vec3::UnitX(), Vec3::UnitZ(), Vec3::UnitY()};
}

void build_links(Weave& weave, int grid_i, int grid_j) {
  // dense (i, j) -> ring lookup, then the four grid neighbours of every ring
  std::vector<int> index_of(static_cast<size_t>(grid_i) * grid_j, -1);
  for (int ring = 0; ring < weave.size(); ++ring) {
    index_of[weave.grid[ring][0] * grid_j + weave.grid[ring][1]] = ring;
  }
  auto at = [&](int i, int j) {
    if (i < 0 || j < 0 || i >= grid_i || j >= grid_j) return -1;
    return index_of[i * grid_j + j];
  };
  weave.neighbours.assign(weave.size(), {-1, -1, -1, -1});
  for (int ring = 0; ring < weave.size(); ++ring) {
    const auto [i, j] = weave.grid[ring];
    weave.neighbours[ring] = {at(i - 1, j), at(i + 1, j), at(i, j - 1), at(i, j + 1)};
    for (int other : {weave.neighbours[ring][1], weave.neighbours[ring][3]}) {
      if (other >= 0) weave.links.push_back({std::min(ring, other), std::max(ring, other)});
    }
  }
  std::sort(weave.links.begin(), weave.links.end(), [](const RingPair& x, const RingPair& y) {
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  });
}

}  // namespace

int Weave::ring_at_row_col(int row, int col) const {
  if (row < 0 || row >= rows || col < 0 || col >= cols) return -1;
  return row * cols + col;
}

Weave make_weave(const WeaveSpec& spec, const RingGeometry& ring) {
  Weave weave;
  weave.type = spec.type;
  weave.rows = spec.type == WeaveType::chain ? 1 : spec.rows;
  weave.cols = spec.cols;
  const SheetAxes axes = sheet_axes(spec.plane);
  weave.row_axis = axes.row;
  weave.advance_axis = axes.advance;
  weave.normal_axis = axes.normal;

  const int n = weave.rows * weave.cols;
  weave.grid.resize(n);
  weave.row_col.resize(n);
  weave.parity.resize(n);
  weave.rest_position.resize(3, n);
  weave.rest_orientation.resize(4, n);

  Mat3 sheet;
  sheet.col(0) = axes.row, sheet.col(1) = axes.normal, sheet.col(2) = axes.advance;
  const Quat flat(sheet);
  const double inner = ring.inner_diameter();

  auto place = [&](int index, double along_row, double along_advance, const Quat& q) {
    weave.rest_position.col(index) =
        spec.center + along_row * axes.row + along_advance * axes.advance;
    weave.rest_orientation.col(index) << q.w(), q.x(), q.y(), q.z();
  };

  if (spec.type == WeaveType::chain) {
    // straight chain along the row axis; odd rings turned a quarter turn about it
    const double spacing = spec.spacing * inner;
    const Quat quarter(Eigen::AngleAxisd(0.5 * std::numbers::pi, axes.row));
    for (int k = 0; k < n; ++k) {
      weave.grid[k] = {k, 0};
      weave.row_col[k] = {0, k};
      weave.parity[k] = k % 2 == 0 ? 1 : -1;
      place(k, (k - 0.5 * (n - 1)) * spacing, 0.0, k % 2 == 0 ? flat : quarter * flat);
    }
    build_links(weave, n, 1);
  } else if (spec.type == WeaveType::grid) {
    // square grid of flat point masses, rows along the row axis
    const double width = (weave.cols - 1) * spec.spacing, height = (weave.rows - 1) * spec.spacing;
    for (int r = 0; r < weave.rows; ++r) {
      for (int k = 0; k < weave.cols; ++k) {
        const int index = r * weave.cols + k;
        weave.grid[index] = {k, r};
        weave.row_col[index] = {r, k};
        weave.parity[index] = (r + k) % 2 == 0 ? 1 : -1;
        place(index, k * spec.spacing - 0.5 * width, r * spec.spacing - 0.5 * height, flat);
      }
    }
    build_links(weave, weave.cols, weave.rows);
  } else {
    // rows of rings leaning alternately by +-tilt about the advance axis; odd rows shifted by half
    const double in_row = kFourInOneRowSpacing * inner;
    const double advance = kFourInOneRowAdvance * inner;
    const Quat lean_pos(Eigen::AngleAxisd(kFourInOneTiltRad, axes.advance));
    const Quat lean_neg(Eigen::AngleAxisd(-kFourInOneTiltRad, axes.advance));
    const double width = (weave.cols - 1 + (weave.rows > 1 ? 0.5 : 0.0)) * in_row;
    const double height = (weave.rows - 1) * advance;
    const int offset = (weave.rows - 1) / 2;
    for (int r = 0; r < weave.rows; ++r) {
      for (int k = 0; k < weave.cols; ++k) {
        const int index = r * weave.cols + k;
        weave.grid[index] = {k + (r + 1) / 2, k - r / 2 + offset};
        weave.row_col[index] = {r, k};
        weave.parity[index] = r % 2 == 0 ? 1 : -1;
        place(index, (k + 0.5 * (r % 2)) * in_row - 0.5 * width, r * advance - 0.5 * height,
              (r % 2 == 0 ? lean_pos : lean_neg) * flat);
      }
    }
    build_links(weave, weave.cols + weave.rows / 2 + 1, weave.cols + offset + 1);
  }
  return weave;
}

std::vector<double> ring_masses(const Scene& scene, const Weave& weave) {
  std::vector<double> mass(weave.size(), scene.ring.mass());
  for (const Load& load : scene.loads) {
    const int ring = weave.ring_at_row_col(load.row, load.col);
    if (ring >= 0) mass[ring] *= load.mass_factor;
  }
  return mass;
}

std::vector<int> resolve_pins(const Scene& scene, const Weave& weave) {
  std::vector<int> pinned;
  for (size_t p = 0; p < scene.pins.size(); ++p) {
    const PinSpec& pin = scene.pins[p];
    const std::string key = "pins[" + std::to_string(p) + "]";
    switch (pin.kind) {
      case PinSpec::Kind::ring: {
        const int ring = weave.ring_at_row_col(pin.row, pin.col);
        if (ring < 0) {
          throw SceneError(scene.file + ": key '" + key + ".ring': ring (row " +
                           std::to_string(pin.row) + ", col " + std::to_string(pin.col) +
                           ") does not exist in a " + std::to_string(weave.rows) + "x" +
                           std::to_string(weave.cols) + " weave");
        }
        pinned.push_back(ring);
        break;
      }
      case PinSpec::Kind::edge: {
        // the edge's rings only: a walk over the whole sheet costs its size (16.7 million rings
        // for the largest one a scene may ask for)
        const bool row = pin.which == "top" || pin.which == "bottom";
        if (!row && pin.which != "left" && pin.which != "right") break;
        const int at = pin.which == "top" || pin.which == "left" ? 0
                       : row                                     ? weave.rows - 1
                                                                 : weave.cols - 1;
        for (int k = 0; k < (row ? weave.cols : weave.rows); ++k)
          pinned.push_back(row ? weave.ring_at_row_col(at, k) : weave.ring_at_row_col(k, at));
        break;
      }
      case PinSpec::Kind::corner: {
        const int r = pin.which.starts_with("top") ? 0 : weave.rows - 1;
        const int k = pin.which.ends_with("left") ? 0 : weave.cols - 1;
        pinned.push_back(weave.ring_at_row_col(r, k));
        break;
      }
    }
  }
  std::sort(pinned.begin(), pinned.end());
  pinned.erase(std::unique(pinned.begin(), pinned.end()), pinned.end());
  return pinned;
}

}  // namespace chainmail

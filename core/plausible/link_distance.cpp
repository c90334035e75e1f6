#include "core/plausible/link_distance.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/circle_contact.hpp"
#include "core/geometry.hpp"

namespace chainmail {
namespace {

constexpr double kPi = std::numbers::pi;

// the rings at centre distance d along x: linked, and their wires clear of each other
bool linked_and_clear(const Vec3& axis_first, const Vec3& axis_second, double d,
                      const RingGeometry& ring) {
  const double c = ring.centre_radius;
  const Circle first{Vec3::Zero(), axis_first, c};
  const Circle second{Vec3(d, 0.0, 0.0), axis_second, c};
  if (!circles_linked(first, second)) return false;
  const ClosestPoints p = closest_points(circle_frame(first.centre, first.normal, c),
                                         circle_frame(second.centre, second.normal, c));
  return p.distance >= 2.0 * ring.wire_radius;
}

// the index and fraction of x on a grid of `nodes` over [0, span], clamped
void grid_cell(double x, double span, int nodes, int& index, double& fraction) {
  const double u = std::clamp(x / span, 0.0, 1.0) * (nodes - 1);
  index = std::min(static_cast<int>(u), nodes - 2);
  fraction = u - index;
}

}  // namespace

LinkOrientation link_orientation(const Vec3& axis_first, const Vec3& axis_second,
                                 const Vec3& centre_line) {
  const Vec3 u = centre_line.normalized();
  // each axis turned to point along the line (a ring turned over is the same ring)
  const Vec3 a = axis_first.dot(u) < 0.0 ? Vec3(-axis_first) : axis_first;
  const Vec3 b = axis_second.dot(u) < 0.0 ? Vec3(-axis_second) : axis_second;
  LinkOrientation o;
  o.tilt_first = std::asin(std::clamp(a.normalized().dot(u), 0.0, 1.0));
  o.tilt_second = std::asin(std::clamp(b.normalized().dot(u), 0.0, 1.0));
  const Vec3 pa = a - a.dot(u) * u, pb = b - b.dot(u) * u;
  // the angle between the parts normal to the line; either is absent for a ring facing the other
  o.twist = std::atan2(pa.cross(pb).norm(), pa.dot(pb));
  return o;
}

void link_axes(const LinkOrientation& o, Vec3& axis_first, Vec3& axis_second) {
  // both axes lean towards +x by their tilt; their parts in the y/z plane are `twist` apart
  axis_first = Vec3(std::sin(o.tilt_first), std::cos(o.tilt_first), 0.0);
  axis_second = Vec3(std::sin(o.tilt_second), std::cos(o.tilt_second) * std::cos(o.twist),
                     std::cos(o.tilt_second) * std::sin(o.twist));
}

double max_link_distance(const LinkOrientation& orientation, const RingGeometry& ring) {
  Vec3 first, second;
  link_axes(orientation, first, second);
  const double c = ring.centre_radius;
  const double step = c / 64.0, end = 2.0 * c + 2.0 * ring.wire_radius;
  // the last scanned distance that is linked and clear
  double lo = -1.0;
  for (double d = 0.0; d <= end; d += step) {
    if (linked_and_clear(first, second, d, ring)) lo = d;
  }
  if (lo < 0.0) return 0.0;
  double hi = lo + step;
  for (int k = 0; k < 60 && hi - lo > 1e-15 * c; ++k) {
    const double mid = 0.5 * (lo + hi);
    (linked_and_clear(first, second, mid, ring) ? lo : hi) = mid;
  }
  return lo;
}

LinkDistanceTable::LinkDistanceTable(const RingGeometry& ring, int tilt_nodes, int twist_nodes)
    : tilt_nodes_(std::max(tilt_nodes, 2)), twist_nodes_(std::max(twist_nodes, 2)) {
  value_.resize(static_cast<std::size_t>(tilt_nodes_) * tilt_nodes_ * twist_nodes_);
  for (int i = 0; i < tilt_nodes_; ++i) {
    for (int j = 0; j < tilt_nodes_; ++j) {
      for (int k = 0; k < twist_nodes_; ++k) {
        // the distance is symmetric in the two rings: fill the lower triangle from the upper
        const std::size_t at = (static_cast<std::size_t>(i) * tilt_nodes_ + j) * twist_nodes_ + k;
        value_[at] =
            j < i ? value_[(static_cast<std::size_t>(j) * tilt_nodes_ + i) * twist_nodes_ + k]
                  : max_link_distance(node(i, j, k), ring);
      }
    }
  }
}

LinkOrientation LinkDistanceTable::node(int i, int j, int k) const {
  LinkOrientation o;
  o.tilt_first = 0.5 * kPi * i / (tilt_nodes_ - 1);
  o.tilt_second = 0.5 * kPi * j / (tilt_nodes_ - 1);
  o.twist = kPi * k / (twist_nodes_ - 1);
  return o;
}

double LinkDistanceTable::max_distance(const LinkOrientation& o) const {
  int i, j, k;
  double fi, fj, fk;
  grid_cell(o.tilt_first, 0.5 * kPi, tilt_nodes_, i, fi);
  grid_cell(o.tilt_second, 0.5 * kPi, tilt_nodes_, j, fj);
  grid_cell(o.twist, kPi, twist_nodes_, k, fk);
  double sum = 0.0;
  for (int di = 0; di < 2; ++di) {
    for (int dj = 0; dj < 2; ++dj) {
      for (int dk = 0; dk < 2; ++dk) {
        const double weight = (di ? fi : 1.0 - fi) * (dj ? fj : 1.0 - fj) * (dk ? fk : 1.0 - fk);
        sum += weight * at(i + di, j + dj, k + dk);
      }
    }
  }
  return sum;
}

double LinkDistanceTable::max_distance(const Vec3& axis_first, const Vec3& axis_second,
                                       const Vec3& centre_line) const {
  return max_distance(link_orientation(axis_first, axis_second, centre_line));
}

double exact_max_link_distance(const RingGeometry& ring, const Vec3& first, const Vec3& second,
                               const Vec3& direction) {
  return max_link_distance(link_orientation(first.normalized(), second.normalized(), direction),
                           ring);
}

double four_in_one_link_reach(const RingGeometry& ring, double lean, double alpha) {
  // sheet frame: rows along X, rows advance along Z, sheet normal Y; the model swivels a ring
  // about the row normal (Z here) one way, its neighbours the other way
  const Vec3 mine = Eigen::AngleAxisd(lean, Vec3::UnitZ()) * Vec3::UnitY();
  const Vec3 theirs = Eigen::AngleAxisd(-lean, Vec3::UnitZ()) * Vec3::UnitY();
  return exact_max_link_distance(ring, mine, theirs, Vec3(std::cos(alpha), 0.0, std::sin(alpha)));
}

double four_in_one_rest_link_angle() {
  return std::atan2(kFourInOneRowAdvance, 0.5 * kFourInOneRowSpacing);
}

double weave_max_link_distance(const Weave& weave, const RingGeometry& ring,
                               double extended_swivel) {
  switch (weave.type) {
    case WeaveType::chain:
      // the model turns each ring a quarter turn from the last, both across the chain
      return exact_max_link_distance(ring, Vec3::UnitY(), Vec3::UnitZ(), Vec3::UnitX());
    case WeaveType::four_in_one:
      return four_in_one_link_reach(ring, extended_swivel, four_in_one_rest_link_angle());
    case WeaveType::grid:
      return 0.0;
  }
  return 0.0;
}

}  // namespace chainmail

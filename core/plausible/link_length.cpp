#include "core/plausible/link_length.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "core/geometry.hpp"
#include "core/plausible/link_distance.hpp"

namespace chainmail {

double exact_max_link_distance(const RingGeometry& ring, const Vec3& first, const Vec3& second,
                               const Vec3& direction) {
  // one geometric truth with the rigid-torus model: the same exact search over the pair's
  // relative orientation (core/link_distance)
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

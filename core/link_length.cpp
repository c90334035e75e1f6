#include "core/link_length.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "core/geometry.hpp"

namespace chainmail {

double exact_max_link_distance(const RingGeometry& ring, const Vec3& first, const Vec3& second,
                               const Vec3& direction) {
  const double c = ring.centre_radius, a = ring.wire_radius;
  const double top = ring.inner_diameter(), bottom = 2.0 * a;
  const Vec3 u = direction.normalized();
  const Circle one{Vec3::Zero(), first.normalized(), c};
  auto valid = [&](double d) {
    const Circle other{d * u, second.normalized(), c};
    return circles_linked(one, other) && !circles_closer_than(one, other, 2.0 * a).has_value();
  };
  // the largest valid distance: scan down from ID, then bisect the step where it turns valid
  constexpr int kScan = 48;
  const double step = (top - bottom) / kScan;
  if (valid(top)) return top;
  for (int k = 1; k <= kScan; ++k) {
    const double d = top - k * step;
    if (!valid(d)) continue;
    double lo = d, hi = d + step;  // lo valid, hi not
    for (int it = 0; it < 40; ++it) {
      const double mid = 0.5 * (lo + hi);
      (valid(mid) ? lo : hi) = mid;
    }
    return lo;
  }
  return 0.0;
}

double four_in_one_link_reach(const RingGeometry& ring, double lean, double alpha) {
  // sheet frame: rows along X, rows advance along Z, sheet normal Y; the model swivels a ring
  // about the row normal (Z here) one way, its neighbours the other way
  const Vec3 mine = Eigen::AngleAxisd(lean, Vec3::UnitZ()) * Vec3::UnitY();
  const Vec3 theirs = Eigen::AngleAxisd(-lean, Vec3::UnitZ()) * Vec3::UnitY();
  return exact_max_link_distance(ring, mine, theirs,
                                 Vec3(std::cos(alpha), 0.0, std::sin(alpha)));
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

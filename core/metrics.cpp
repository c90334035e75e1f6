#include "core/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_set>

#include "core/geometry.hpp"
#include "core/spatial_hash.hpp"

namespace chainmail {

const std::vector<std::string>& metric_names() {
  static const std::vector<std::string> names = {"max_stretch",
                                                 "mean_stretch",
                                                 "penetrating_linked",
                                                 "penetrating_other",
                                                 "penetration_max_linked",
                                                 "penetration_mean_linked",
                                                 "penetration_max_other",
                                                 "penetration_mean_other",
                                                 "broken_links",
                                                 "false_links",
                                                 "drape_coefficient",
                                                 "drape_rms",
                                                 "kinetic_energy",
                                                 "max_speed"};
  return names;
}

double metric_value(const Metrics& m, const std::string& name) {
  const double absent = std::numeric_limits<double>::quiet_NaN();
  if (name == "max_stretch") return m.max_stretch;
  if (name == "mean_stretch") return m.mean_stretch;
  if (name == "penetrating_linked") return static_cast<double>(m.penetrating_linked);
  if (name == "penetrating_other") return static_cast<double>(m.penetrating_other);
  if (name == "penetration_max_linked") return m.penetration_max_linked;
  if (name == "penetration_mean_linked") return m.penetration_mean_linked;
  if (name == "penetration_max_other") return m.penetration_max_other;
  if (name == "penetration_mean_other") return m.penetration_mean_other;
  if (name == "broken_links") return static_cast<double>(m.broken_links);
  if (name == "false_links") return static_cast<double>(m.false_links);
  if (name == "drape_coefficient") return m.drape_coefficient.value_or(absent);
  if (name == "drape_rms") return m.drape_rms.value_or(absent);
  if (name == "kinetic_energy") return m.kinetic_energy;
  if (name == "max_speed") return m.max_speed;
  return absent;
}

namespace {

// interpenetrating pairs and their depths, m
struct Penetration {
  long long count = 0;
  double max = 0.0, sum = 0.0;
  double mean() const { return count > 0 ? sum / count : 0.0; }
};

// tori of tube radius a interpenetrate when their centre circles come closer than 2a - tolerance;
// the depth is 2a minus that distance
void add_penetration(const Circle& first, const Circle& second, double a, double tolerance,
                     Penetration& into) {
  const std::optional<double> distance = circles_closer_than(first, second, 2.0 * a - tolerance);
  if (!distance) return;
  ++into.count;
  into.max = std::max(into.max, 2.0 * a - *distance);
  into.sum += 2.0 * a - *distance;
}

// linked pairs: stretch, interpenetration, still linked. A plain grid (the cloth scenes) has no
// rings (circles empty): its stretch is against each edge's rest length, the ring counts stay 0
void measure_links(const RingFrame& frame, const Weave& weave, const RingGeometry& ring,
                   const std::vector<Circle>& circles, Metrics& m) {
  const bool rings = !circles.empty();
  const double a = ring.wire_radius, tolerance = 1e-3 * a;
  double stretch_sum = 0.0;
  Penetration depth;
  for (const RingPair& link : weave.links) {
    const double length = (frame.position.col(link.a) - frame.position.col(link.b)).norm();
    const double rest =
        rings ? ring.max_link_distance()
              : (weave.rest_position.col(link.a) - weave.rest_position.col(link.b)).norm();
    m.max_stretch = std::max(m.max_stretch, length / rest);
    stretch_sum += length / rest;
    if (!rings) continue;
    add_penetration(circles[link.a], circles[link.b], a, tolerance, depth);
    m.broken_links += !circles_linked(circles[link.a], circles[link.b]);
  }
  if (!weave.links.empty()) m.mean_stretch = stretch_sum / weave.links.size();
  m.penetrating_linked = depth.count;
  m.penetration_max_linked = depth.max;
  m.penetration_mean_linked = depth.mean();
}

// other pairs: only those whose centres are close enough to touch or link (< 2c + 2a)
void measure_other_pairs(const RingFrame& frame, const Weave& weave, const RingGeometry& ring,
                         const std::vector<Circle>& circles, Metrics& m) {
  const int n = frame.size();
  const double a = ring.wire_radius, c = ring.centre_radius;
  std::unordered_set<long long> linked;
  for (const RingPair& link : weave.links)
    linked.insert(static_cast<long long>(link.a) * n + link.b);
  const double reach = 2.0 * c + 2.0 * a;
  Penetration depth;
  SpatialHash hash;
  hash.build(frame.position, reach);
  hash.for_each_pair(frame.position, reach, [&](int i, int j) {
    if (linked.count(static_cast<long long>(i) * n + j)) return;
    add_penetration(circles[i], circles[j], a, 1e-3 * a, depth);
    m.false_links += circles_linked(circles[i], circles[j]);
  });
  m.penetrating_other = depth.count;
  m.penetration_max_other = depth.max;
  m.penetration_mean_other = depth.mean();
}

}  // namespace

Metrics measure(const RingFrame& frame, const Weave& weave, const Scene& scene,
                const MetricOptions& options) {
  Metrics m;
  const int n = frame.size();

  // non-finite entries are counted; geometry on them would be meaningless
  m.non_finite = (!frame.position.array().isFinite()).count() +
                 (!frame.orientation.array().isFinite()).count() +
                 (!frame.velocity.array().isFinite()).count();
  if (m.non_finite > 0) {
    m.max_stretch = m.mean_stretch = m.kinetic_energy = m.max_speed = m.penetration_max_linked =
        m.penetration_mean_linked = m.penetration_max_other = m.penetration_mean_other =
            std::numeric_limits<double>::quiet_NaN();
    return m;
  }

  const bool rings = weave.type != WeaveType::grid;
  std::vector<Circle> circles(rings ? n : 0);
  for (size_t i = 0; i < circles.size(); ++i) {
    circles[i] = ring_circle(frame.position.col(i), frame.quat(static_cast<int>(i)),
                             scene.ring.centre_radius);
  }
  measure_links(frame, weave, scene.ring, circles, m);
  if (options.other_pairs && n > 1 && rings)
    measure_other_pairs(frame, weave, scene.ring, circles, m);

  // drape: Cusick's coefficient against the flat rest layout, only where the scene has a support
  if (scene.support) {
    RingFrame flat;
    flat.position = weave.rest_position;
    m.drape_coefficient = drape_coefficient(frame, flat, *scene.support, scene.ring.centre_radius);
  }

  // motion
  const std::vector<double> mass = ring_masses(scene, weave);
  for (int i = 0; i < n; ++i) {
    const double speed2 = frame.velocity.col(i).squaredNorm();
    m.kinetic_energy += 0.5 * mass[i] * speed2;
    m.max_speed = std::max(m.max_speed, std::sqrt(speed2));
  }
  return m;
}

double drape_rms(const RingFrame& frame, const RingFrame& reference) {
  const int n = std::min(frame.size(), reference.size());
  if (n == 0) return 0.0;
  return std::sqrt(
      (frame.position.leftCols(n) - reference.position.leftCols(n)).colwise().squaredNorm().sum() /
      n);
}

double projected_area(const RingFrame& frame, double centre_radius, double cell) {
  if (frame.size() == 0) return 0.0;
  // rasterise the disks of radius c onto an x/z grid and count covered cells; a frame spread far
  // (a run blowing up) gets coarser cells, so the grid stays within 2^24 cells
  const double r = centre_radius;
  const double x0 = frame.position.row(0).minCoeff() - r, x1 = frame.position.row(0).maxCoeff() + r;
  const double z0 = frame.position.row(2).minCoeff() - r, z1 = frame.position.row(2).maxCoeff() + r;
  if (!std::isfinite(x1 - x0) || !std::isfinite(z1 - z0)) return std::nan("");
  cell = std::max(cell, std::sqrt((x1 - x0) * (z1 - z0) / double(1 << 24)));
  const int nx = static_cast<int>(std::ceil((x1 - x0) / cell)) + 1;
  const int nz = static_cast<int>(std::ceil((z1 - z0) / cell)) + 1;
  std::vector<unsigned char> covered(static_cast<size_t>(nx) * nz, 0);
  const int span = static_cast<int>(std::ceil(r / cell));
  for (int i = 0; i < frame.size(); ++i) {
    const double px = frame.position(0, i), pz = frame.position(2, i);
    const int cx = static_cast<int>((px - x0) / cell), cz = static_cast<int>((pz - z0) / cell);
    covered[static_cast<size_t>(std::min(cx, nx - 1)) * nz + std::min(cz, nz - 1)] = 1;  // its own
    for (int ix = std::max(0, cx - span); ix <= std::min(nx - 1, cx + span); ++ix) {
      for (int iz = std::max(0, cz - span); iz <= std::min(nz - 1, cz + span); ++iz) {
        const double qx = x0 + (ix + 0.5) * cell - px, qz = z0 + (iz + 0.5) * cell - pz;
        if (qx * qx + qz * qz <= r * r) covered[static_cast<size_t>(ix) * nz + iz] = 1;
      }
    }
  }
  long long count = 0;
  for (unsigned char v : covered) count += v;
  return count * cell * cell;
}

double drape_coefficient(const RingFrame& frame, const RingFrame& flat, const Support& support,
                         double centre_radius) {
  const double cell = centre_radius / 4.0;
  const double support_area = M_PI * support.radius * support.radius;
  const double flat_area = projected_area(flat, centre_radius, cell);
  const double shadow = projected_area(frame, centre_radius, cell);
  return (shadow - support_area) / (flat_area - support_area);
}

std::optional<double> catenary_error(const Scene& scene, const Weave& weave,
                                     const RingFrame& frame) {
  if (weave.type != WeaveType::chain) return std::nullopt;
  const std::vector<int> pins = resolve_pins(scene, weave);
  const int n = weave.size();
  if (pins.size() != 2 || pins[0] != 0 || pins[1] != n - 1) return std::nullopt;
  const Vec3 down = scene.gravity.normalized();
  const Vec3 p0 = weave.rest_position.col(0), p1 = weave.rest_position.col(n - 1);
  if (std::abs((p1 - p0).dot(down)) > 1e-9) return std::nullopt;  // pins at equal height only
  const double span = (p1 - p0).norm();
  const double length = (n - 1) * scene.ring.max_link_distance();
  if (length <= span) return std::nullopt;
  // catenary parameter A from length = 2 A sinh(span / 2A), by bisection on A
  double lo = 1e-9 * span, hi = 1e6 * span;
  for (int it = 0; it < 200; ++it) {
    const double mid = std::sqrt(lo * hi);
    (2.0 * mid * std::sinh(span / (2.0 * mid)) > length ? lo : hi) = mid;
  }
  const double a = std::sqrt(lo * hi);
  const double expected = a * (std::cosh(span / (2.0 * a)) - 1.0);
  double sag = 0.0;
  for (int i = 0; i < n; ++i) sag = std::max(sag, (frame.position.col(i) - p0).dot(down));
  return std::abs(sag - expected) / expected;
}

}  // namespace chainmail

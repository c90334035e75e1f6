#include "core/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace chainmail {
namespace {

// orthonormal tangent pair for a unit normal (Duff et al. 2017, branchless ONB)
void tangent_basis(const Vec3& n, Vec3& t0, Vec3& t1) {
  const double sign = std::copysign(1.0, n.z());
  const double a = -1.0 / (sign + n.z());
  const double b = n.x() * n.y() * a;
  t0 = Vec3(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
  t1 = Vec3(b, sign + n.y() * n.y() * a, -n.y());
}

struct CircleParam {
  Vec3 centre, t0, t1;
  double radius;
  Vec3 at(double s) const { return centre + radius * (std::cos(s) * t0 + std::sin(s) * t1); }
};

CircleParam parametrise(const Circle& circle) {
  CircleParam p{circle.centre, Vec3(), Vec3(), circle.radius};
  tangent_basis(circle.normal, p.t0, p.t1);
  return p;
}

}  // namespace

double point_circle_distance(const Vec3& p, const Circle& circle) {
  const Vec3 d = p - circle.centre;
  const double h = d.dot(circle.normal);
  const double r = (d - h * circle.normal).norm();
  const double radial = r - circle.radius;
  return std::sqrt(h * h + radial * radial);
}

double circle_circle_distance(const Circle& first, const Circle& second, int samples) {
  const CircleParam b = parametrise(second);
  const double step = 2.0 * std::numbers::pi / samples;
  auto f = [&](double s) { return point_circle_distance(b.at(s), first); };

  std::vector<double> value(samples);
  for (int k = 0; k < samples; ++k) value[k] = f(k * step);

  double best = *std::min_element(value.begin(), value.end());
  // refine every sampled local minimum: golden-section search on its two neighbouring intervals
  const double inv_phi = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int k = 0; k < samples; ++k) {
    const double prev = value[(k + samples - 1) % samples];
    const double next = value[(k + 1) % samples];
    if (value[k] > prev || value[k] > next) continue;
    double lo = (k - 1) * step, hi = (k + 1) * step;
    double x1 = hi - inv_phi * (hi - lo), x2 = lo + inv_phi * (hi - lo);
    double f1 = f(x1), f2 = f(x2);
    while (hi - lo > 1e-11) {
      if (f1 < f2) {
        hi = x2, x2 = x1, f2 = f1;
        x1 = hi - inv_phi * (hi - lo), f1 = f(x1);
      } else {
        lo = x1, x1 = x2, f1 = f2;
        x2 = lo + inv_phi * (hi - lo), f2 = f(x2);
      }
    }
    best = std::min({best, f1, f2});
  }
  return best;
}

bool tori_interpenetrate(const Circle& first, const Circle& second, double wire_radius,
                         double tolerance) {
  const double limit = 2.0 * wire_radius - tolerance;
  // centre circles farther apart than the sum of radii plus the wire cannot touch
  if ((first.centre - second.centre).norm() > first.radius + second.radius + limit) return false;
  // a sample below the limit decides at once; a sampled minimum can only be refined downwards by
  // the distance function's Lipschitz bound (1 per unit arc length) times half a sample step, so
  // minima above limit + that bound need no refinement
  const int samples = 32;
  const CircleParam b = parametrise(second);
  const double step = 2.0 * std::numbers::pi / samples;
  double value[samples];
  for (int k = 0; k < samples; ++k) {
    value[k] = point_circle_distance(b.at(k * step), first);
    if (value[k] < limit) return true;
  }
  const double slack = second.radius * 0.5 * step;
  double lowest = value[0];
  for (int k = 1; k < samples; ++k) lowest = std::min(lowest, value[k]);
  if (lowest > limit + slack) return false;
  return circle_circle_distance(first, second, samples) < limit;
}

int disk_crossings(const Circle& first, const Circle& second, int samples) {
  // far apart: the second circle cannot reach the first's disk
  if ((first.centre - second.centre).norm() > first.radius + second.radius) return 0;
  const CircleParam b = parametrise(second);
  const double step = 2.0 * std::numbers::pi / samples;
  auto height = [&](double s) { return (b.at(s) - first.centre).dot(first.normal); };

  // start at an irrational phase so symmetric cases do not put a sample exactly on the plane
  const double phase = 0.1234567891;
  int crossings = 0;
  double s0 = phase, h0 = height(s0);
  for (int k = 1; k <= samples; ++k) {
    const double s1 = phase + k * step, h1 = height(s1);
    if ((h0 < 0.0) != (h1 < 0.0)) {
      // bisect the crossing, then ask whether it lies inside the disk
      double lo = s0, hi = s1, hlo = h0;
      for (int it = 0; it < 50; ++it) {
        const double mid = 0.5 * (lo + hi), hm = height(mid);
        if ((hm < 0.0) == (hlo < 0.0))
          lo = mid, hlo = hm;
        else
          hi = mid;
      }
      const Vec3 q = b.at(0.5 * (lo + hi)) - first.centre;
      const Vec3 in_plane = q - q.dot(first.normal) * first.normal;
      if (in_plane.norm() < first.radius) ++crossings;
    }
    s0 = s1, h0 = h1;
  }
  return crossings;
}

Circle ring_circle(const Vec3& centre, const Quat& orientation, double centre_radius) {
  return Circle{centre, (orientation * Vec3::UnitY()).normalized(), centre_radius};
}

}  // namespace chainmail

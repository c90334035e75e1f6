#include "core/geometry.hpp"

#include "core/circle_contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
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

// golden-section refinement of every sampled local minimum of the distance from `second`'s
// points to `first`; value holds the distances at s = k * 2 pi / samples
double refined_minimum(const Circle& first, const CircleParam& b, const double* value,
                       int samples) {
  const double step = 2.0 * std::numbers::pi / samples;
  auto f = [&](double s) { return point_circle_distance(b.at(s), first); };
  double best = *std::min_element(value, value + samples);
  const double inv_phi = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int k = 0; k < samples; ++k) {
    const double prev = value[(k + samples - 1) % samples];
    const double next = value[(k + 1) % samples];
    if (value[k] > prev || value[k] > next) continue;
    // search the two intervals beside the sampled minimum
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

// the most the distance can fall between samples: it moves by at most r2 per radian of the second
// circle's angle, so a minimum lies at most r2 times half a sample step below the nearest sample
double sample_slack(const Circle& second) {
  return second.radius * std::numbers::pi / CirclePairDistance::kSamples;
}

// the torus tests' cheap part on the closed-form distance of core/circle_contact: fills f with the
// squared distance at CirclePairDistance's sample angles and returns false when the circles
// certainly stay at least `limit` apart
bool sample_near(const CirclePairDistance& pair, const Circle& first, const Circle& second,
                 double limit, double* f) {
  // centre circles farther apart than the sum of radii plus the limit cannot come that close
  const double reach = first.radius + second.radius + limit;
  if ((first.centre - second.centre).squaredNorm() > reach * reach) return false;
  pair.sample(f);
  const double lowest = *std::min_element(f, f + CirclePairDistance::kSamples);
  return std::sqrt(lowest) <= limit + sample_slack(second);
}

// the smallest distance Newton's method reaches from the refine starts (for_each_refine_start)
// within `limit` plus the slack of a minimum below it
double refined_below(const CirclePairDistance& pair, const Circle& second, double limit,
                     const double* f) {
  constexpr int count = CirclePairDistance::kSamples;
  const CirclePairDistance::Samples& angle = CirclePairDistance::samples();
  const double within = limit + sample_slack(second);
  double best = std::sqrt(*std::min_element(f, f + count));
  for_each_refine_start(f, count, [&](int k) {
    if (f[k] > within * within) return;
    best = std::min(best, pair.refine(angle.c[k], angle.s[k], 40, 1e-13).distance);
  });
  return best;
}

// tolerance of the linking test, m: heights within it of the first circle's plane count as on the
// plane, in-plane distances within it of the radius as on the rim. Two parts:
// - round-off: a height is a dot product of coordinates, off by a few ulps of the largest
//   coordinate involved (centres, radii); 64 machine epsilons of their sum bounds that with margin,
//   so a rigidly moved coplanar pair (the mass-spring frames: neighbours share one normal) stays in
//   the band wherever it is placed.
// - 1e-9 of the radii: frames that were computed (solves, orientations from neighbour vectors)
//   carry ~1e-12 m of jitter on mm rings; the band absorbs it and still hides no physical
//   crossing: interlocked rings cross each other's plane at an angle of order one, by a good part
//   of c. Only tilts below ~1e-9 rad count as coplanar, and coplanar circles are not linked.
double linking_band(const Circle& first, const Circle& second) {
  const double size = first.radius + second.radius;
  const double coordinates =
      first.centre.cwiseAbs().maxCoeff() + second.centre.cwiseAbs().maxCoeff() + size;
  return 1e-9 * size + 64.0 * std::numeric_limits<double>::epsilon() * coordinates;
}

// disk_crossings' test that the second circle's heights over the first's plane (h0 at its centre)
// pass beyond the band on both sides, from a bound on the amplitude, without the tangent basis:
// alpha^2 + beta^2 is |n|^2 - (n . n2)^2 up to rounding (normals unit to within 1e-12), so where
// even the bound leaves no crossing neither does the exact amplitude
bool may_reach_both_sides(const Circle& first, const Circle& second, double h0, double band) {
  const double along = first.normal.dot(second.normal);
  const double tilt = std::sqrt(std::max(0.0, first.normal.squaredNorm() - along * along) + 1e-12);
  return second.radius * tilt - std::abs(h0) > band;
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
  std::vector<double> value(samples);  // (samples) m
  for (int k = 0; k < samples; ++k) value[k] = point_circle_distance(b.at(k * step), first);
  return refined_minimum(first, b, value.data(), samples);
}

std::optional<double> circles_closer_than(const Circle& first, const Circle& second, double limit) {
  const CircleFrame a = circle_frame(first.centre, first.normal, first.radius);
  const CircleFrame b = circle_frame(second.centre, second.normal, second.radius);
  const CirclePairDistance pair(a, b);
  double f[CirclePairDistance::kSamples];  // m^2
  if (!sample_near(pair, first, second, limit, f)) return std::nullopt;
  const double distance = refined_below(pair, second, limit, f);
  if (distance < limit) return distance;
  return std::nullopt;
}

bool tori_interpenetrate(const Circle& first, const Circle& second, double wire_radius,
                         double tolerance) {
  const double limit = 2.0 * wire_radius - tolerance;
  const CircleFrame a = circle_frame(first.centre, first.normal, first.radius);
  const CircleFrame b = circle_frame(second.centre, second.normal, second.radius);
  const CirclePairDistance pair(a, b);
  double f[CirclePairDistance::kSamples];  // m^2
  if (!sample_near(pair, first, second, limit, f)) return false;
  // a sample below the limit decides without refining
  if (std::sqrt(*std::min_element(f, f + CirclePairDistance::kSamples)) < limit) return true;
  return refined_below(pair, second, limit, f) < limit;
}

int disk_crossings(const Circle& first, const Circle& second) {
  // far apart: the second circle cannot reach the first's disk
  const Vec3 offset = second.centre - first.centre;  // m
  const double reach = first.radius + second.radius;
  if (offset.squaredNorm() > reach * reach) return 0;
  const Vec3& n = first.normal;
  const double h0 = offset.dot(n);
  const double band = linking_band(first, second);
  if (!may_reach_both_sides(first, second, h0, band)) return 0;
  Vec3 t0, t1;
  tangent_basis(second.normal, t0, t1);
  // the second circle's height above the first's plane is exactly a sinusoid,
  // h(s) = h0 + r2 (alpha cos s + beta sin s): no sampling, its extremes are h0 -+ amplitude
  const double alpha = t0.dot(n), beta = t1.dot(n);
  // (not std::hypot: alpha and beta are at most 1, and hypot's care for overflow costs as much as
  // the rest of the test)
  const double tilt = std::sqrt(alpha * alpha + beta * beta), amplitude = second.radius * tilt;
  // a crossing needs heights strictly beyond the band on both sides; otherwise the circles are
  // coplanar (never linked) or touch the plane without crossing it
  if (amplitude - std::abs(h0) <= band) return 0;
  // the two roots: (cos s, sin s) = k u -+ w u_perp, u = (alpha, beta) / tilt, k = -h0 / amplitude
  const double k = -h0 / amplitude, w = std::sqrt(1.0 - k * k);
  const double ua = alpha / tilt, ub = beta / tilt;
  // open disk: a crossing on the rim, within the band, is outside
  const double inner = first.radius - band;
  if (inner <= 0.0) return 0;
  int crossings = 0;
  for (const double m : {w, -w}) {
    const Vec3 q = offset + second.radius * ((k * ua - m * ub) * t0 + (k * ub + m * ua) * t1);
    const double h = q.dot(n);
    crossings += q.squaredNorm() - h * h < inner * inner;
  }
  return crossings;
}

bool circle_may_pass_within_radius(const Circle& circle, const Vec3& point) {
  // a circle of radius r passes within (1 + 1e-6) r of a point at height h over its plane and
  // in-plane distance rho only where (rho - r)^2 + h^2 < ((1 + 1e-6) r)^2
  const Vec3 offset = point - circle.centre;                                       // m
  const double h = offset.dot(circle.normal);                                      // m
  const double distance2 = offset.squaredNorm();                                   // m^2
  const double rho = std::sqrt(std::max(0.0, distance2 - h * h)) - circle.radius;  // m
  const double within = (1.0 + 1e-6) * circle.radius;                              // m
  return rho * rho + h * h < within * within;
}

bool circles_may_link(const Circle& first, const Circle& second) {
  const Vec3 offset = second.centre - first.centre;  // m
  const double reach = first.radius + second.radius;
  if (offset.squaredNorm() > reach * reach) return false;
  // with the least band disk_crossings uses, 1e-9 of the radii
  if (!may_reach_both_sides(first, second, offset.dot(first.normal), 1e-9 * reach)) return false;
  return circle_may_pass_within_radius(second, first.centre) &&
         circle_may_pass_within_radius(first, second.centre);
}

Circle ring_circle(const Vec3& centre, const Quat& orientation, double centre_radius) {
  return Circle{centre, (orientation * Vec3::UnitY()).normalized(), centre_radius};
}

}  // namespace chainmail

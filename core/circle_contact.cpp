#include "core/circle_contact.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace chainmail {
namespace {

// (c, s) turned by about `step` rad (exactly by atan(step)): a Newton step needs no more
void turn(double& c, double& s, double step) {
  const double nc = c - s * step, ns = s + c * step;
  const double inv = inverse_norm(nc * nc + ns * ns);
  c = nc * inv, s = ns * inv;
}

// (cos, sin) of `count` equally spaced angles from 0
template <int count>
const std::array<std::array<double, 2>, count>& sample_angles() {
  static const auto table = [] {
    std::array<std::array<double, 2>, count> t{};
    for (int k = 0; k < count; ++k) {
      const double angle = 2.0 * std::numbers::pi * k / count;
      t[k] = {std::cos(angle), std::sin(angle)};
    }
    return t;
  }();
  return table;
}

// (c, s) scaled to unit length; the zero vector is angle 0
void unit_angle(double& c, double& s) {
  const double norm2 = c * c + s * s;
  const double inv = norm2 > 0.0 ? inverse_norm(norm2) : 0.0;
  c = norm2 > 0.0 ? c * inv : 1.0, s = norm2 > 0.0 ? s * inv : 0.0;
}

// the second circle's point at the unit angle (c, s) and the first circle's point nearest to it
ClosestPoints points_at_angle(const CircleFrame& a, const CircleFrame& b, double c, double s) {
  ClosestPoints out;
  out.cos_t = c, out.sin_t = s;
  out.second = b.at(c, s);
  const Vec3 w = out.second - a.centre;
  const double height = w.dot(a.normal);  // m, above the first circle's plane
  const Vec3 in_plane = w - height * a.normal;
  const double rho = in_plane.norm();
  // on the first circle's axis every point of it is equally near: take its angle 0
  if (rho <= 1e-12 * a.radius) {
    out.first = a.at(1, 0);
    out.distance = (out.second - out.first).norm();
    return out;
  }
  out.first = a.centre + (a.radius / rho) * in_plane;
  // the distance in the half-plane through the axis (it waits on rho's root, not on `first`)
  const double across = rho - a.radius;  // m
  out.distance = std::sqrt(across * across + height * height);
  return out;
}

}  // namespace

const CirclePairDistance::Samples& CirclePairDistance::samples() {
  static const Samples table = [] {
    Samples t{};
    for (int k = 0; k < kSamples; ++k) {
      t.c[k] = sample_angles<kSamples>()[k][0];
      t.s[k] = sample_angles<kSamples>()[k][1];
    }
    return t;
  }();
  return table;
}

CirclePairDistance::CirclePairDistance(const CircleFrame& a, const CircleFrame& b)
    : first_(&a), second_(&b) {
  const Vec3 w0 = b.centre - a.centre;
  r1_ = a.radius, r2_ = b.radius;
  k0_ = w0.squaredNorm() + r2_ * r2_;
  wu_ = w0.dot(b.x), wv_ = w0.dot(b.z);
  h0_ = w0.dot(a.normal), hu_ = b.x.dot(a.normal), hv_ = b.z.dot(a.normal);
  const double size = r1_ + r2_ + std::sqrt(w0.squaredNorm());
  flat_ = 1e-14 * size * size;
}

void CirclePairDistance::sample(double* f) const {
  // written out so that the loop vectorises
  const Samples& t = samples();
  const double a = 2.0 * r2_ * wu_, b = 2.0 * r2_ * wv_, c = r2_ * hu_, d = r2_ * hv_;
  const double twice_r1 = 2.0 * r1_, r1_squared = r1_ * r1_;
  for (int k = 0; k < kSamples; ++k) {
    const double ww = k0_ + a * t.c[k] + b * t.s[k];
    const double h = h0_ + c * t.c[k] + d * t.s[k];
    const double g = std::max(ww - h * h, 0.0);
    f[k] = ww - twice_r1 * std::sqrt(g) + r1_squared;
  }
}

CirclePairDistance::Slope CirclePairDistance::slope(double c, double s) const {
  const double ww = k0_ + 2.0 * r2_ * (wu_ * c + wv_ * s);
  const double ww1 = 2.0 * r2_ * (wv_ * c - wu_ * s);
  const double ww2 = -2.0 * r2_ * (wu_ * c + wv_ * s);
  const double h = h0_ + r2_ * (hu_ * c + hv_ * s);
  const double h1 = r2_ * (hv_ * c - hu_ * s);
  const double h2 = h0_ - h;
  const double g = std::max(ww - h * h, 0.0);  // rho^2
  const double g1 = ww1 - 2.0 * h * h1;
  const double g2 = ww2 - 2.0 * (h1 * h1 + h * h2);
  const double rho = std::sqrt(g);
  // f' = ww1 - r1 g1 / rho and f'' = ww2 - r1 (g2 - g1^2 / (2 g)) / rho, times rho^3 = rho g
  Slope out{ww - 2.0 * r1_ * rho + r1_ * r1_, 0.0, 0.0, rho};
  if (rho > 0.0) {
    out.f1 = (ww1 * rho - r1_ * g1) * g;
    out.f2 = ww2 * rho * g - r1_ * (g2 * g - 0.5 * g1 * g1);
    out.rho3 = rho * g;
  }
  return out;
}

// Newton on f' with two safeguards: where f is not convex (or on the first circle's axis, a cusp
// that is a maximum of f) walk a quarter radian downhill, and halve any step that makes f grow
void CirclePairDistance::newton(double& c, double& s, int max_steps, double tolerance) const {
  if (max_steps <= 0) return;
  Slope at = slope(c, s);
  for (int k = 0; k < max_steps; ++k) {
    double step;
    if (at.rho <= 1e-12 * r1_) {
      step = 0.25;
    } else if (std::abs(at.f1) <= flat_ * at.rho3) {
      return;  // a minimum to round-off, or a circle of minima (coaxial circles)
    } else if (at.f2 > 0.0) {
      step = std::clamp(-at.f1 / at.f2, -0.5, 0.5);
    } else {
      step = at.f1 > 0.0 ? -0.25 : 0.25;
    }
    // a small last step needs no check: the quadratic model holds there
    if (k + 1 == max_steps && std::abs(step) < 0.05) {
      turn(c, s, step);
      return;
    }
    for (int halving = 0;; ++halving) {
      double nc = c, ns = s;
      turn(nc, ns, step);
      const Slope next = slope(nc, ns);
      if (next.f <= at.f + flat_ || halving == 12) {
        c = nc, s = ns, at = next;
        break;
      }
      step *= 0.5;
    }
    if (std::abs(step) < tolerance) return;
  }
}

ClosestPoints CirclePairDistance::points_at(double c, double s) const {
  return points_at_angle(*first_, *second_, c, s);
}

ClosestPoints CirclePairDistance::refine(double cos_t, double sin_t, int max_steps,
                                         double tolerance) const {
  double c = cos_t, s = sin_t;
  unit_angle(c, s);
  newton(c, s, max_steps, tolerance);
  return points_at(c, s);
}

CircleFrame ring_frame(const Vec3& centre, const Quat& orientation, double centre_radius) {
  const Mat3 r = orientation.toRotationMatrix();
  return CircleFrame{centre, r.col(0), r.col(2), r.col(1), centre_radius};
}

CircleFrame circle_frame(const Vec3& centre, const Vec3& normal, double radius) {
  const Vec3 n = normal.normalized();
  const Vec3 x = n.unitOrthogonal();
  return CircleFrame{centre, x, x.cross(n), n, radius};
}

ClosestPoints refine_closest_points(const CircleFrame& first, const CircleFrame& second,
                                    double cos_t, double sin_t, int max_steps, double tolerance) {
  if (max_steps > 0)
    return CirclePairDistance(first, second).refine(cos_t, sin_t, max_steps, tolerance);
  // no step: the points at the start angle need none of the distance's terms
  unit_angle(cos_t, sin_t);
  return points_at_angle(first, second, cos_t, sin_t);
}

int local_closest_points(const CircleFrame& first, const CircleFrame& second, ClosestPoints* out,
                         int capacity, int samples, double tolerance) {
  const CirclePairDistance pair(first, second);
  const auto& angles16 = sample_angles<16>();
  const auto& angles32 = sample_angles<32>();
  const int count = samples > 16 ? 32 : 16;
  const auto angle = [&](int k) { return count == 32 ? angles32[k] : angles16[k]; };
  std::array<double, 32> f{};  // m^2, f at the samples
  for (int k = 0; k < count; ++k) f[k] = pair.squared(angle(k)[0], angle(k)[1]);

  // from every refine start (for_each_refine_start: a flat f gives none), else from the lowest
  // sample; duplicates (the same minimum from two starts) dropped
  std::array<ClosestPoints, 16> found;
  int n = 0;
  const auto refine_from = [&](int k) {
    const ClosestPoints p = pair.refine(angle(k)[0], angle(k)[1], 40, tolerance);
    const double same = 1e-9 * (first.radius + second.radius);
    for (int j = 0; j < n; ++j) {
      if ((found[j].second - p.second).squaredNorm() <= same * same) return;
    }
    if (n < static_cast<int>(found.size())) found[n++] = p;
  };
  for_each_refine_start(f.data(), count, refine_from);
  if (n == 0)
    refine_from(static_cast<int>(std::min_element(f.begin(), f.begin() + count) - f.begin()));
  std::sort(found.begin(), found.begin() + n,
            [](const ClosestPoints& x, const ClosestPoints& y) { return x.distance < y.distance; });
  const int kept = std::min(n, capacity);
  std::copy(found.begin(), found.begin() + kept, out);
  return kept;
}

ClosestPoints closest_points(const CircleFrame& first, const CircleFrame& second) {
  ClosestPoints best;
  local_closest_points(first, second, &best, 1, 32);
  return best;
}

}  // namespace chainmail

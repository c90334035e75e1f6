// Closest points of two circles in space, exact and fast: the contact of two rings' centre
// circles. The nearest point of a circle to a point is in closed form, so the distance of two
// circles reduces to a function of one angle t on the second circle,
//   f(t) = |Q(t) - P(Q(t))|^2,   P(Q) = the first circle's point nearest to Q,
// whose first and second derivatives are trigonometric polynomials and one square root. A
// safeguarded Newton iteration on f' finds a local minimum: from the last solve's angle (a warm
// start) one or two steps; from scratch, fixed samples of f bracket every local minimum first.
// Angles are kept as unit vectors (cos t, sin t): no trigonometric call in the iteration.
#pragma once

#include <cmath>

#include "core/types.hpp"

namespace chainmail {

// a circle with its in-plane axes: points centre + radius (cos s x + sin s z), normal = z x x
// (a ring's local X, Z and Y, see ring.hpp)
struct CircleFrame {
  Vec3 centre;          // m
  Vec3 x, z;            // unit, orthogonal, in the circle's plane
  Vec3 normal;          // unit
  double radius = 0.0;  // m
  Vec3 at(double cos_s, double sin_s) const { return centre + radius * (cos_s * x + sin_s * z); }
};

// a ring's centre circle: the orientation's local X and Z span the plane, local Y is the normal
CircleFrame ring_frame(const Vec3& centre, const Quat& orientation, double centre_radius);
// a circle given by its normal alone: in-plane axes chosen from the normal
CircleFrame circle_frame(const Vec3& centre, const Vec3& normal, double radius);

struct ClosestPoints {
  Vec3 first = Vec3::Zero();        // m, on the first circle
  Vec3 second = Vec3::Zero();       // m, on the second circle
  double distance = 0.0;            // m, |second - first|
  double cos_t = 1.0, sin_t = 0.0;  // the second circle's angle at `second` (the next warm start)
};

// the squared distance of two circles as a function of the second one's angle t, for one pair in
// one pose: f(t) = |w|^2 - 2 r1 rho + r1^2 with w = Q(t) - c1, h = w . n1 and rho^2 = |w|^2 - h^2
// (the law of cosines in the half-plane through the first circle's axis and Q); |w|^2 and h are
// first-order trigonometric polynomials in t, so f costs a few products and one square root
class CirclePairDistance {
 public:
  CirclePairDistance(const CircleFrame& first, const CircleFrame& second);

  // f at the angle (cos t, sin t), m^2
  double squared(double c, double s) const {
    const double ww = k0_ + 2.0 * r2_ * (wu_ * c + wv_ * s);
    const double h = h0_ + r2_ * (hu_ * c + hv_ * s);
    const double g = ww - h * h;
    return ww - 2.0 * r1_ * std::sqrt(g > 0.0 ? g : 0.0) + r1_ * r1_;
  }
  // f at the kSamples angles 2 pi k / kSamples, m^2
  static constexpr int kSamples = 32;
  void sample(double* f) const;
  // the local minimum nearest downhill from (cos t, sin t): safeguarded Newton on f' (see
  // refine_closest_points)
  ClosestPoints refine(double cos_t, double sin_t, int max_steps, double tolerance) const;

  // the sample angles
  struct Samples {
    double c[kSamples], s[kSamples];  // cos, sin
  };
  static const Samples& samples();

 private:
  // f, and its first two derivatives in t times rho^3 (their ratio, the Newton step, then takes
  // one division, and their signs are theirs)
  struct Slope {
    double f;           // m^2
    double f1, f2;      // m^5
    double rho;         // m, distance of Q(t) from the first circle's axis
    double rho3 = 0.0;  // m^3
  };
  Slope slope(double c, double s) const;
  void newton(double& c, double& s, int max_steps, double tolerance) const;
  ClosestPoints points_at(double c, double s) const;

  const CircleFrame* first_;
  const CircleFrame* second_;
  double k0_, wu_, wv_;  // |w|^2 = k0 + 2 r2 (wu cos t + wv sin t), m^2 and m
  double h0_, hu_, hv_;  // h = h0 + r2 (hu cos t + hv sin t), m and 1
  double r1_, r2_;       // m
  double flat_;          // m^2, a slope |f'| below this is round-off (coaxial circles)
};

// the local minimum of the distance nearest downhill from the second circle's angle
// (cos_t, sin_t); stops when a Newton step is below `tolerance` rad or after `max_steps` steps
// (0: the points at the start angle, an upper bound of the minimum's distance).
// Degenerate pairs are exact too: coaxial circles (every angle a minimum) keep the start angle;
// a point of the second circle on the first one's axis (every point of the first equally near)
// takes the first circle's angle 0.
ClosestPoints refine_closest_points(const CircleFrame& first, const CircleFrame& second,
                                    double cos_t, double sin_t, int max_steps = 40,
                                    double tolerance = 1e-13);

// the samples of f (count of them, around the circle) to refine from: each sampled local minimum
// (no higher than the sample before it, below the one after) and the two beside it, each once, in
// that order; visit(k). Two minima a sample spacing apart (a taut link's wire meets the other ring
// twice, close together) show as one sampled minimum, and the deeper may be the other one
template <class Visit>
void for_each_refine_start(const double* f, int count, Visit&& visit) {
  bool started[64] = {};  // count <= 64
  for (int k = 0; k < count; ++k) {
    const int before = (k + count - 1) % count, after = (k + 1) % count;
    if (f[k] > f[before] || f[k] >= f[after]) continue;
    for (const int start : {k, before, after}) {
      if (!started[start]) started[start] = true, visit(start);
    }
  }
}

// the local minima of the distance, nearest first, each refined to `tolerance`: at most
// `capacity` written to `out`, their count returned (at least 1). The samples (16 or 32 fixed
// angles) decide which minima are found, refined from the starts for_each_refine_start gives: two
// minima a sample spacing apart are both found.
int local_closest_points(const CircleFrame& first, const CircleFrame& second, ClosestPoints* out,
                         int capacity, int samples = 16, double tolerance = 1e-13);

// the global minimum (32 samples, refined to round-off)
ClosestPoints closest_points(const CircleFrame& first, const CircleFrame& second);

}  // namespace chainmail

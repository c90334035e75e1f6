// Closed forms the tests hold the models to: physics written out independently of the code under
// test.
#pragma once

#include <cmath>

namespace chainmail::test {

// sag of the catenary y = A cosh(x / A) of length `length` over the span `span` (equal heights):
// A from length = 2 A sinh(span / 2A) by bisection (the right side falls monotonically in A),
// sag = A (cosh(span / 2A) - 1)
inline double catenary_sag(double span, double length) {
  double lo = 1e-6 * span, hi = 1e6 * span;
  for (int k = 0; k < 200; ++k) {
    const double mid = std::sqrt(lo * hi);
    (2.0 * mid * std::sinh(span / (2.0 * mid)) > length ? lo : hi) = mid;
  }
  const double a = std::sqrt(lo * hi);
  return a * (std::cosh(span / (2.0 * a)) - 1.0);
}

}  // namespace chainmail::test

// core/types.hpp: the inverse norm that renormalises unit vectors and quaternions after every
// contact correction, against 1 / sqrt.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/types.hpp"

namespace chainmail {
namespace {

// near 1 the series is used: it must agree with 1 / sqrt to rounding across its whole range, and
// past it the root itself is taken
TEST(InverseNorm, AgreesWithTheRootToRoundingNearOneAndBeyond) {
  double worst_series = 0.0;
  for (int k = -1000; k <= 1000; ++k) {
    const double n2 = 1.0 + k * 0.999e-7;  // |n2 - 1| < 1e-4: the series
    const double exact = 1.0 / std::sqrt(n2);
    worst_series = std::max(worst_series, std::abs(inverse_norm(n2) - exact) / exact);
  }
  EXPECT_LT(worst_series, 4e-16);
  for (const double n2 : {0.25, 0.9, 0.9999, 1.0001, 1.5, 4.0, 1e6}) {
    EXPECT_NEAR(inverse_norm(n2), 1.0 / std::sqrt(n2), 4e-16 / std::sqrt(n2)) << n2;
  }
  EXPECT_EQ(inverse_norm(1.0), 1.0);
}

}  // namespace
}  // namespace chainmail

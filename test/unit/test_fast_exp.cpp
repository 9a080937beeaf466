// detail/fast_exp.h: the inline exp of the cost against libm, and its macro kept inside the header.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "radar_ndt/registration/detail/fast_exp.h"

using namespace radar_ndt;

#ifdef RADAR_NDT_ALWAYS_INLINE
#error "RADAR_NDT_ALWAYS_INLINE leaks out of radar_ndt/registration/detail/fast_exp.h"
#endif

TEST(FastExp, MatchesLibm) {
  for (double x = -700.0; x <= 0.0; x += 0.37) {
    const double e = std::exp(x);
    EXPECT_NEAR(detail::expNegative(x), e, 1e-8 * e) << x;
  }
  EXPECT_EQ(detail::expNegative(0.0), 1.0);
  // Below the range (and NaN): as at -700, tiny and finite, never NaN or a denormal trap.
  EXPECT_EQ(detail::expNegative(-1e6), detail::expNegative(-700.0));
  EXPECT_EQ(detail::expNegative(std::numeric_limits<double>::quiet_NaN()), detail::expNegative(-700.0));
  EXPECT_GT(detail::expNegative(-700.0), 0.0);
}

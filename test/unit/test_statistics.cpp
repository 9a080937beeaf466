// The one median (radar_ndt/statistics.h).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "radar_ndt/statistics.h"

using namespace radar_ndt;

TEST(Median, OddEvenAndEmpty) {
  EXPECT_EQ(median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(median({4.0, 1.0, 3.0, 2.0}), 2.5) << "the mean of the two middle values";
  EXPECT_EQ(median({0.25, 0.75}), 0.5);
  EXPECT_EQ(median({7.0}), 7.0);
  EXPECT_EQ(median({}), 0.0);
  EXPECT_TRUE(std::isnan(median({}, std::numeric_limits<double>::quiet_NaN())));
  EXPECT_EQ(median({5.0, 5.0, 1.0, 9.0}), 5.0);
}

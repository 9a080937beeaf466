// Radar cycles (io/radar_cycle.h): the reference radar clocks them, every other radar gives its
// latest sweep within one period before; a mounting's 2D yaw.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "radar_ndt/io/radar_cycle.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;

TEST(RadarCycles, ReferenceClocksAndOthersWithinOnePeriod) {
  // Channel 0 every 100 ms; channel 1 offset by 30 ms; channel 2 missing for a while.
  std::vector<SweepStamp> s;
  for (int k = 0; k < 10; ++k) {
    s.push_back({k * 100000, 0});
    s.push_back({k * 100000 + 30000, 1});
    if (k < 3 || k > 6) s.push_back({k * 100000 + 60000, 2});
  }
  std::sort(s.begin(), s.end(),
            [](const SweepStamp& a, const SweepStamp& b) { return a.timestamp_us < b.timestamp_us; });
  const auto plans = planRadarCycles(s, 0);
  ASSERT_EQ(plans.size(), 10u);
  EXPECT_EQ(plans[0].members.size(), 1u);  // nothing before the first reference sweep
  for (std::size_t k = 1; k < plans.size(); ++k) {
    const std::int64_t t = s[plans[k].reference].timestamp_us;
    for (const auto m : plans[k].members) {
      EXPECT_LE(s[m].timestamp_us, t);
      EXPECT_GT(s[m].timestamp_us, t - 100000);
    }
    const bool has2 = (k - 1 < 3 || k - 1 > 6);
    EXPECT_EQ(plans[k].members.size(), has2 ? 3u : 2u) << k;
  }
}

TEST(RadarCycles, AMountingsYawIsItsForwardAxisInTheVehicleFrame) {
  Eigen::Isometry3d rear_left = Eigen::Isometry3d::Identity();
  rear_left.translate(Eigen::Vector3d(-0.5, 0.8, 0.6));
  rear_left.rotate(Eigen::AngleAxisd(0.75 * kPi, Eigen::Vector3d::UnitZ()));
  const SensorMounting m = toMounting(rear_left);
  EXPECT_TRUE(m.valid);
  EXPECT_DOUBLE_EQ(m.x, -0.5);
  EXPECT_DOUBLE_EQ(m.y, 0.8);
  EXPECT_NEAR(m.yaw, 0.75 * kPi, 1e-12);
}

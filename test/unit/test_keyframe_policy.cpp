// KeyframePolicy: which scan the next one is matched against.
#include <gtest/gtest.h>

#include <stdexcept>

#include "radar_ndt/odometry/keyframe_policy.h"

using namespace radar_ndt;

TEST(KeyframePolicy, AMatchedScanFarEnoughOrTurnedEnoughReplacesTheKeyframe) {
  KeyframePolicy policy;  // 8 m, 0.1 rad
  policy.reset(Pose2(10.0, 0.0, 0.0), 1000);
  EXPECT_EQ(policy.stamp(), 1000);
  EXPECT_FALSE(policy.replaceAfter(true, Pose2(17.9, 0.0, 0.0), true));
  EXPECT_TRUE(policy.replaceAfter(true, Pose2(18.0, 0.0, 0.0), true));
  EXPECT_TRUE(policy.replaceAfter(true, Pose2(11.0, 0.0, 0.1), true));
  EXPECT_FALSE(policy.replaceAfter(true, Pose2(11.0, 0.0, -0.099), true));
  // Distances are measured in the keyframe's frame.
  policy.reset(Pose2(0.0, 0.0, 1.5), 2000);
  EXPECT_TRUE(policy.replaceAfter(true, Pose2(0.6, 8.0, 1.5), true));
}

TEST(KeyframePolicy, OneFailedScanIsNeverTheTargetTwoInARowAre) {
  KeyframePolicy policy;
  policy.reset(Pose2::Zero(), 0);
  EXPECT_FALSE(policy.replaceAfter(false, Pose2(30.0, 0.0, 0.0), true))
      << "one failure: maybe a corrupt or all-noise scan";
  EXPECT_TRUE(policy.replaceAfter(false, Pose2(31.0, 0.0, 0.0), true)) << "two in a row: the keyframe no longer fits";
  EXPECT_FALSE(policy.replaceAfter(true, Pose2(1.0, 0.0, 0.0), true)) << "a match resets the count";
  EXPECT_FALSE(policy.replaceAfter(false, Pose2(1.0, 0.0, 0.0), true));
  EXPECT_TRUE(policy.replaceAfter(false, Pose2(1.0, 0.0, 0.0), false)) << "a keyframe too small to match against";
}

TEST(KeyframePolicy, DistanceZeroMatchesScanToScan) {
  KeyframeOptions o;
  o.distance = 0.0;
  KeyframePolicy policy(o);
  policy.reset(Pose2::Zero(), 0);
  EXPECT_TRUE(policy.replaceAfter(true, Pose2(0.01, 0.0, 0.0), true));
  o.distance = -1;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

// KeyframeTarget: the scanning odometry's keyframe at its reference time, its copy as given, and
// what the matcher holds of it (the target model is built once per keyframe).
#include <gtest/gtest.h>

#include "radar_ndt/odometry/keyframe_target.h"
#include "radar_ndt/odometry/motion_compensation.h"

using namespace radar_ndt;

namespace {
using Cloud = pcl::PointCloud<PointRadar>;

/// Our matcher, counting the targets it is given and keeping the last.
struct CountingMatcher : WeightedNDT2D<PointRadar, PointRadar> {
  int targets = 0;
  Cloud::ConstPtr last;
  void setInputTarget(const Cloud::ConstPtr& cloud) override {
    ++targets;
    last = cloud;
    WeightedNDT2D<PointRadar, PointRadar>::setInputTarget(cloud);
  }
};

Cloud sweep() {  // points along a line, each with its time offset within the sweep
  Cloud c;
  for (int i = 0; i < 40; ++i) {
    PointRadar p(10.0f, -2.0f + 0.1f * static_cast<float>(i), 0.f, 0.8f);
    p.time_offset = -0.125f + 0.25f * static_cast<float>(i) / 40.f;
    c.push_back(p);
  }
  return c;
}
}  // namespace

TEST(KeyframeTarget, TheFirstScanIsKeptAsGivenUntilAVelocityIsKnown) {
  KeyframeTarget target;
  EXPECT_EQ(target.size(), 0u);
  const Cloud scan = sweep();
  target.resetFirst(scan);
  EXPECT_FALSE(target.compensated());
  ASSERT_EQ(target.size(), scan.size());
  EXPECT_EQ((*target.cloud())[5].x, scan[5].x) << "not moved";
  EXPECT_EQ((*target.cloud())[5].time_offset, 0.f) << "its time offsets zeroed";
  const Eigen::Vector3d v(8.0, 0.0, 0.2);
  target.compensateFirst(v);
  EXPECT_TRUE(target.compensated());
  Cloud expected;
  compensateMotion(scan, v, expected);
  EXPECT_EQ((*target.cloud())[5].x, expected[5].x) << "moved with the first velocity";
  const float once = (*target.cloud())[5].x;
  target.compensateFirst(Eigen::Vector3d(1.0, 0.0, 0.0));
  EXPECT_EQ((*target.cloud())[5].x, once) << "compensated once only";
}

TEST(KeyframeTarget, TheMatcherIsGivenEachKeyframeOnceAndARoundsCopyIsUndone) {
  KeyframeTarget target;
  CountingMatcher matcher;
  const Cloud scan = sweep();
  const Eigen::Vector3d v(8.0, 0.0, 0.2);
  target.reset(scan, &v);
  EXPECT_TRUE(target.compensated());
  target.giveTo(matcher);
  target.giveTo(matcher);
  EXPECT_EQ(matcher.targets, 1) << "a kept keyframe is not given again";
  EXPECT_EQ(matcher.last, target.cloud());
  target.giveRecompensated(matcher, Eigen::Vector3d(9.0, 0.0, 0.0));
  EXPECT_EQ(matcher.targets, 2);
  EXPECT_NE(matcher.last, target.cloud()) << "a compensation round's copy, not the keyframe";
  Cloud expected;
  compensateMotion(scan, Eigen::Vector3d(9.0, 0.0, 0.0), expected);
  EXPECT_EQ((*matcher.last)[7].x, expected[7].x) << "the scan as given, moved with the round's velocity";
  target.restore(matcher);
  EXPECT_EQ(matcher.targets, 3);
  EXPECT_EQ(matcher.last, target.cloud());
  target.restore(matcher);
  target.giveTo(matcher);
  EXPECT_EQ(matcher.targets, 3) << "nothing to undo, nothing to give";
  target.reset(scan, nullptr);  // compensation off: the scan as given
  EXPECT_EQ((*target.cloud())[7].x, scan[7].x);
  target.giveTo(matcher);
  EXPECT_EQ(matcher.targets, 4) << "a new keyframe is given";
}

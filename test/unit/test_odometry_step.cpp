// The step log both odometries share (skipped and bridged steps, the trajectory) and the
// constant-velocity model they predict from.
#include <gtest/gtest.h>

#include "radar_ndt/odometry/motion_model.h"
#include "radar_ndt/odometry/odometry_step.h"

using namespace radar_ndt;

TEST(ConstantVelocityModel, PredictsAlongTheArcAndRescalesLinearly) {
  ConstantVelocityModel m;
  EXPECT_FALSE(m.hasVelocity());
  EXPECT_EQ(m.predict(0.25), Pose2::Zero()) << "no motion yet: standing still";
  const Pose2 arc = integrateVelocity(Eigen::Vector3d(10.0, 0.0, 0.4), 0.25);
  m.update(arc, 0.25);
  EXPECT_TRUE(m.hasVelocity());
  EXPECT_LT((m.velocity() - Eigen::Vector3d(10.0, 0.0, 0.4)).norm(), 1e-12);
  EXPECT_LT((m.predict(0.5) - integrateVelocity(Eigen::Vector3d(10.0, 0.0, 0.4), 0.5)).norm(), 1e-12);
  EXPECT_LT((m.rescaledTranslation(0.5) - 2.0 * arc.head<2>()).norm(), 1e-12);
  m.update(Pose2(1.0, 0.0, 0.0), 0.0);  // a first step: no interval
  EXPECT_FALSE(m.hasVelocity());
}

TEST(StepLog, SkipsStepsThatDoNotAdvanceAndBridgesUnreadableOnes) {
  StepLog log;
  ConstantVelocityModel model;
  EXPECT_EQ(log.bridge(500, model).status, StepStatus::Skipped) << "nothing to continue from";
  OdometryStep first = log.begin(1000000);
  first.status = StepStatus::First;
  log.add(first);
  OdometryStep second = log.begin(1250000);
  second.status = StepStatus::Matched;
  second.motion = Pose2(2.5, 0.0, 0.0);
  second.pose = second.motion;
  log.add(second);
  model.update(second.motion, 0.25);
  EXPECT_EQ(log.previous()->timestamp_us, 1250000);
  const OdometryStep& bridged = log.bridge(1750000, model);
  EXPECT_EQ(bridged.status, StepStatus::Bridged);
  EXPECT_LT((bridged.pose - Pose2(7.5, 0.0, 0.0)).norm(), 1e-12) << "continues at the last velocity over 0.5 s";
  EXPECT_EQ(log.previous()->timestamp_us, 1250000) << "a bridged step is not matched against";
  EXPECT_EQ(log.bridge(1250000, model).status, StepStatus::Skipped) << "not after the last processed step";
  const OdometryStep same = log.begin(1250000);
  EXPECT_EQ(log.addSkipped(same, *log.previous()).pose, second.pose);
  const auto& c = log.counters();
  EXPECT_EQ(c.cycles, 6u);
  EXPECT_EQ(c.skipped, 3u);
  EXPECT_EQ(c.bridged, 1u);
  const Trajectory t = log.trajectory();
  ASSERT_EQ(t.size(), 3u) << "first, matched and bridged: skipped steps have no pose";
  EXPECT_DOUBLE_EQ(t.stamps[2], 1.75);
  EXPECT_EQ(toString(StepStatus::DeadReckoned), std::string("dead-reckoned"));
}

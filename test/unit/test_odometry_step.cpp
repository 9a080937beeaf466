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

// The counters come from the steps, in one place: each recorded step counts once by its status,
// so the statuses add up to the steps; the attempts' outcomes, the slow grid, the halved shift and
// a reused ego-velocity come from the step's own fields.
TEST(StepLog, CountersAreDerivedFromTheStepsAndAddUp) {
  StepLog log;
  auto record = [&](std::int64_t t, StepStatus status, auto&& set) {
    OdometryStep s = log.begin(t);
    s.status = status;
    set(s);
    return log.add(s);
  };
  auto none = [](OdometryStep&) {};
  record(0, StepStatus::First, none);
  record(100, StepStatus::Matched, [](OdometryStep& s) { s.slow = true; });
  record(200, StepStatus::Retried, [](OdometryStep& s) {
    s.attempts_not_converged = 2;
    s.shift_halved = true;
  });
  record(300, StepStatus::Fallback, [](OdometryStep& s) {
    s.attempts_rejected = 3;
    s.attempts_poor_fit = 1;
    s.slow = true;  // a slow fallback is not a slow match
  });
  record(400, StepStatus::DeadReckoned, [](OdometryStep& s) { s.too_few_points = true; });
  record(500, StepStatus::DeadReckoned, [](OdometryStep& s) { s.velocity_valid = false; });  // no matcher
  log.bridge(600, ConstantVelocityModel());
  log.addSkipped(log.begin(600), log.steps().back());
  const OdometryCounters& c = log.counters();
  EXPECT_EQ(c.cycles, 8u);
  EXPECT_EQ(c.first + c.matched + c.retried + c.fallbacks + c.dead_reckoned + c.bridged + c.skipped, c.cycles);
  EXPECT_EQ(c.first, 1u);
  EXPECT_EQ(c.matched, 1u);
  EXPECT_EQ(c.retried, 1u);
  EXPECT_EQ(c.fallbacks, 1u);
  EXPECT_EQ(c.dead_reckoned, 2u);
  EXPECT_EQ(c.too_few_points, 1u);
  EXPECT_EQ(c.bridged, 1u);
  EXPECT_EQ(c.skipped, 1u);
  EXPECT_EQ(c.slow, 1u);
  EXPECT_EQ(c.shift_halved, 1u);
  EXPECT_EQ(c.not_converged, 2u);
  EXPECT_EQ(c.rejected, 3u);
  EXPECT_EQ(c.poor_fit, 1u);
  EXPECT_EQ(c.stale_velocity, 1u);
  // Unmatched: the fallback, the scan with too few points, the bridged one (3 of 6 matchable steps).
  EXPECT_EQ(c.unmatched(), 3u);
  EXPECT_EQ(c.matchable(), 6u);
  EXPECT_FALSE(c.mostlyUnmatched()) << "half is not most";
  record(700, StepStatus::DeadReckoned, [](OdometryStep& s) { s.too_few_points = true; });
  EXPECT_TRUE(log.counters().mostlyUnmatched()) << "4 of 7";
}

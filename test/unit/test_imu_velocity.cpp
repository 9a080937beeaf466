// The body velocity an IMU predicts from the last scan's (radar_ndt/odometry/imu_velocity.h): on
// a simulated drive with exact IMU readings it follows the true body velocity through an
// acceleration, a turn and over a hill; its covariance grows with the time since the last accepted one.
#include <gtest/gtest.h>

#include <vector>

#include "drive_support.h"
#include "radar_ndt/odometry/imu_velocity.h"
#include "radar_ndt/sim/motion_6dof.h"

using namespace radar_ndt;

namespace {

Eigen::Vector3d bodyVelocityAt(const sim::Motion6Dof& motion, double t) {
  return motion.pose(t).linear().transpose() * motion.velocity(t);
}

}  // namespace

TEST(ImuVelocity, FollowsTheBodysVelocityThroughAccelerationAndTurns) {
  const sim::Motion6Dof motion(test::curveDrive(40));
  const std::vector<ImuSample> imu = sim::simulateImu6(motion, sim::imu6Preset("none"), 1);
  // From the first message after each start, to a time between messages (the last reading held
  // over the few milliseconds left): speeding up at 54 s; at 62 and 75 s in the curve, where the
  // body's velocity stays what it was only because ω × v takes up the centripetal acceleration.
  for (const double start : {54.0, 62.0, 75.0}) {
    std::size_t i = 0;
    while (imu[i].t < start) ++i;
    const double t0 = imu[i].t, t1 = t0 + 1.0023;
    const Eigen::Vector3d predicted =
        predictBodyVelocity(motion.pose(t0).linear(), bodyVelocityAt(motion, t0), imu[i], imu.begin(), imu.end(), t1,
                            Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 9.81);
    const Eigen::Vector3d truth = bodyVelocityAt(motion, t1);
    if (start < 60) {
      EXPECT_GT((truth - bodyVelocityAt(motion, t0)).norm(), 1.0) << "speeding up";
    }
    EXPECT_LT((predicted - truth).norm(), 0.02)
        << start << ": " << predicted.transpose() << " against " << truth.transpose();
  }
  // The biases are taken off the readings: a reading with an accelerometer bias, the bias given.
  std::vector<ImuSample> biased = imu;
  for (ImuSample& s : biased) s.accel += Eigen::Vector3d(0.3, -0.2, 0.1);
  std::size_t i = 0;
  while (biased[i].t < 62.0) ++i;
  const double t1 = biased[i].t + 1.0;
  const Eigen::Vector3d with_bias = predictBodyVelocity(
      motion.pose(biased[i].t).linear(), bodyVelocityAt(motion, biased[i].t), biased[i], biased.begin(), biased.end(),
      t1, Eigen::Vector3d::Zero(), Eigen::Vector3d(0.3, -0.2, 0.1), 9.81);
  EXPECT_LT((with_bias - bodyVelocityAt(motion, t1)).norm(), 0.02);
}

TEST(ImuVelocity, TheCovarianceGrowsLinearlyWithTheTimeSinceTheLastAccepted) {
  const Eigen::Matrix3d accepted = 0.01 * Eigen::Matrix3d::Identity();
  EXPECT_TRUE(predictedVelocityCovariance(accepted, 0.0, 0.0, 1.0).isApprox(accepted));
  EXPECT_NEAR(predictedVelocityCovariance(accepted, 0.0, 0.2, 1.0)(2, 2), 0.01 + 0.04, 1e-12);
  EXPECT_NEAR(predictedVelocityCovariance(accepted, 2.0, 0.0, 0.5)(0, 0), 0.01 + 1.0, 1e-12);
  EXPECT_NEAR(predictedVelocityCovariance(accepted, 4.0, 0.2, 0.5)(1, 1), 0.01 + 0.04 + 4.0, 1e-12);
  EXPECT_EQ(predictedVelocityCovariance(accepted, 4.0, 0.2, 0.5)(0, 1), 0.0);
}

// Real 6-DoF motion driving the 4D simulator (radar_ndt/sim/motion_6dof.h): the spline, the 6-axis
// IMU that rides it (checked by running doppler-imu on its exact readings), the world around a
// path, and a short sequence along a real hand-held trajectory.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "drive_support.h"
#include "radar_ndt/frontend/ego_velocity_3d.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/odometry/doppler_imu.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/sim/motion_6dof.h"

using namespace radar_ndt;

namespace {

const std::string kCarried = std::string(RADAR_NDT_SHARED_DATA) + "/handheld-6dof/carried_1.txt";

/// A walk at 4 Hz: a circle of 8 m radius at 1.3 m/s with a gentle climb and roll/pitch wobble.
Trajectory circleWalk(double seconds) {
  Trajectory t;
  for (double s = 0; s <= seconds; s += 0.25) {
    const double a = 1.3 * s / 8.0;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(8 * std::sin(a), 8 * (1 - std::cos(a)), 0.01 * s);
    T.linear() = (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(0.05 * std::sin(1.3 * s), Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(0.04 * std::sin(0.9 * s), Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    t.stamps.push_back(100 + s);
    t.poses.push_back(T);
  }
  return t;
}

}  // namespace

TEST(Motion6Dof, FollowsItsTrajectoryWithAStillStart) {
  const Trajectory walk = circleWalk(60);
  const sim::Motion6Dof m(walk);
  EXPECT_NEAR(m.start(), 98.0, 1e-9);  // two still seconds before the file
  EXPECT_LT(m.velocity(98.5).norm(), 1e-6);
  EXPECT_LT(m.angularVelocity(98.5).norm(), 1e-6);
  for (double t = 110; t < 150; t += 7.3) {
    Eigen::Isometry3d truth;
    ASSERT_TRUE(walk.poseAt(t, &truth));
    EXPECT_LT((m.pose(t).translation() - truth.translation()).norm(), 0.02) << t;
    EXPECT_NEAR(m.velocity(t).norm(), 1.3, 0.02) << t;
    EXPECT_NEAR(m.angularVelocity(t).z(), 1.3 / 8.0, 0.05) << t;
  }
  EXPECT_NEAR(m.length(), 1.3 * 60, 1.0);
  EXPECT_THROW(sim::Motion6Dof(Trajectory{}), std::invalid_argument);
}

TEST(Motion6Dof, DopplerImuOnItsExactImuRecoversTheMotion) {
  // The IMU's readings are the motion's derivatives with gravity: integrated by doppler-imu with
  // the exact body velocity they give the motion back. Gravity on another axis, or of the wrong
  // sign, does not.
  const sim::Motion6Dof m(circleWalk(60));
  const std::vector<ImuSample> imu = sim::simulateImu6(m, sim::imu6Preset("none"), 1);
  ASSERT_NEAR(imu.front().accel.z(), 9.81, 1e-6);  // still, level: +g along the body's up
  std::vector<BodyVelocitySample> v;
  for (double t = m.start() + 0.05; t <= m.end(); t += 0.1)
    v.push_back({t, m.pose(t).linear().transpose() * m.velocity(t), true});
  const DopplerImuResult r = runDopplerImu(imu, v);
  EXPECT_TRUE(r.problems.empty()) << r.problems.front();
  const Eigen::Isometry3d start = m.pose(r.trajectory.stamps.front());
  for (std::size_t k = 0; k < r.trajectory.size(); k += 50) {
    const Eigen::Isometry3d truth = start.inverse() * m.pose(r.trajectory.stamps[k]);
    // The estimate's world is levelled with the start's heading: start is level and still.
    EXPECT_LT((r.trajectory.poses[k].translation() - truth.translation()).norm(), 0.1) << k;
    EXPECT_LT(Eigen::AngleAxisd(r.trajectory.poses[k].linear().transpose() * truth.linear()).angle(), 0.01) << k;
  }
}

TEST(Motion6Dof, AMemsImuDriftsAsItsGradeSays) {
  const sim::Motion6Dof m(circleWalk(20));
  const std::vector<ImuSample> none = sim::simulateImu6(m, sim::imu6Preset("none"), 2);
  const std::vector<ImuSample> mems = sim::simulateImu6(m, sim::imu6Preset("mems"), 2);
  ASSERT_EQ(none.size(), mems.size());
  Eigen::Vector3d gyro_err = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < 200; ++k) gyro_err += (mems[k].gyro - none[k].gyro) / 200.0;  // the first second
  // The turn-on bias (0.2°/s, 1σ) dominates the first second's mean error.
  EXPECT_GT(gyro_err.norm(), 1e-4);
  EXPECT_LT(gyro_err.norm(), 0.05);
  EXPECT_THROW(sim::imu6Preset("consumer"), std::invalid_argument);
}

// A rig that ends its path still faces a world: it goes on past the path's end along the last
// heading (a car's street 100 m, a walker's corridor 15 m), not only beside the path it drove.
TEST(Motion6Dof, TheWorldGoesOnPastThePathsEnd) {
  for (const bool car : {true, false}) {
    const sim::Motion6Dof m(car ? test::curveDrive(30) : circleWalk(20));
    const Eigen::Vector3d end = m.pose(m.end()).translation();
    Eigen::Vector3d heading = end - m.pose(m.end() - 0.5).translation();
    heading.z() = 0;
    heading.normalize();
    const double reach = car ? 100.0 : 15.0;
    std::size_t ahead = 0;
    for (const auto& b : sim::worldAlongPath(m, car, 3).boxes) {
      const double along = (0.5 * (b.min + b.max) - end).dot(heading);
      if (along > 0.2 * reach && along < reach + 5.0) ++ahead;
    }
    EXPECT_GT(ahead, car ? 100u : 15u) << (car ? "car" : "hand-held");
  }
}

TEST(Motion6Dof, ARealHandheldWalkDrivesTheTiPreset) {
  if (!std::filesystem::exists(kCarried)) GTEST_SKIP() << "no " << kCarried << " (../shared/data is absent)";
  const sim::Motion6Dof m(readTrajectory(kCarried));
  EXPECT_NEAR(m.length(), 295.0, 15.0);  // the README's length
  const sim::World3D world = sim::worldAlongPath(m, false, 3);
  EXPECT_GT(world.boxes.size(), 300u);
  // Nothing in the rig's way: no box within 0.5 m of the path.
  for (double t = m.start(); t < m.end(); t += 1.0) {
    const Eigen::Vector3d c = m.pose(t).translation();
    for (const auto& b : world.boxes)
      ASSERT_FALSE(c.x() > b.min.x() - 0.5 && c.x() < b.max.x() + 0.5 && c.y() > b.min.y() - 0.5 &&
                   c.y() < b.max.y() + 0.5 && c.z() > b.min.z() && c.z() < b.max.z())
          << t;
  }
  // Its first 20 s with the TI preset at 10 Hz: scans with detections whose Doppler the 3D
  // estimator turns back into the rig's velocity.
  const Trajectory first = [&] {
    Trajectory t = readTrajectory(kCarried);
    const double end = t.stamps.front() + 20;
    while (t.stamps.back() > end) {
      t.stamps.pop_back();
      t.poses.pop_back();
    }
    return t;
  }();
  const sim::Motion6Dof short_walk(first);
  const auto seq = sim::simulateRadar4DSequence(short_walk, sim::worldAlongPath(short_walk, false, 3),
                                                sim::radar4DPreset("ti_iwr6843_rio"), 10, sim::imu6Preset("mems"), 4);
  ASSERT_GT(seq.scans.size(), 200u);
  std::vector<double> counts, errors;
  for (std::size_t k = 0; k < seq.scans.size(); ++k) {
    counts.push_back(static_cast<double>(seq.scans[k].size()));
    const EgoVelocity3D e = EgoVelocity3DEstimator().estimate(seq.scans[k]);
    if (e.valid)
      errors.push_back(
          (e.velocity - seq.truth.poses[k].linear().transpose() * short_walk.velocity(seq.stamps[k])).norm());
  }
  std::sort(counts.begin(), counts.end());
  std::sort(errors.begin(), errors.end());
  EXPECT_GT(counts[counts.size() / 2], 15.0);
  EXPECT_GT(errors.size(), seq.scans.size() * 8 / 10);
  EXPECT_LT(errors[errors.size() / 2], 0.1);
  EXPECT_GT(seq.imu.size(), 200u * 20);
}

namespace {

TEST(Motion6Dof, AMountedRadarSeesItsOwnVelocityAndTheBodysComesBackThroughTheMounting) {
  // A radar 0.5 m ahead of and 0.3 m left of the body's origin, looking left (yaw 90°) and tilted
  // down 10°: its Doppler is its own motion, the body's plus the lever arm's turn, in its own axes;
  // bodyVelocity() with the mounting and the body's rate gives the body's velocity back.
  const sim::Motion6Dof m(circleWalk(30));
  Eigen::Isometry3d mounting = Eigen::Isometry3d::Identity();
  mounting.translation() = Eigen::Vector3d(0.5, 0.3, 0.0);
  mounting.linear() = (Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()) *
                       Eigen::AngleAxisd(10 * kPi / 180, Eigen::Vector3d::UnitY()))
                          .toRotationMatrix();
  const auto seq =
      sim::simulateRadar4DSequence(m, sim::worldAlongPath(m, false, 5), sim::radar4DPreset("ti_iwr6843_rio"), 10,
                                   sim::imu6Preset("none"), 6, mounting);
  ASSERT_GT(seq.scans.size(), 250u);
  std::vector<double> errors;
  for (std::size_t k = 0; k < seq.scans.size(); ++k) {
    const EgoVelocity3D e = EgoVelocity3DEstimator().estimate(seq.scans[k]);
    if (!e.valid) continue;
    const double t = seq.stamps[k];
    const Eigen::Vector3d body = seq.truth.poses[k].linear().transpose() * m.velocity(t);
    errors.push_back((bodyVelocity(mounting, e.velocity, m.angularVelocity(t)) - body).norm());
  }
  std::sort(errors.begin(), errors.end());
  ASSERT_GT(errors.size(), seq.scans.size() * 7 / 10);
  EXPECT_LT(errors[errors.size() / 2], 0.1);  // the walk is at 1.3 m/s
}

}  // namespace

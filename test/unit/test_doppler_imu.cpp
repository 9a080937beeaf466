// The doppler-imu baseline (radar_ndt/odometry/doppler_imu.h) on a known 6-DoF motion: an IMU and
// body velocities made from its exact derivatives, with and without a MEMS gyro's errors; bad IMU
// streams.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "radar_ndt/odometry/doppler_imu.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;

namespace {

constexpr double kG = 9.81;

/// A hand-held walk: still for the first second, then forward at about 1.3 m/s along a slow turn,
/// with a step's bounce and the roll and pitch wobble of a carried rig.
Eigen::Isometry3d truthAt(double t) {
  const double s = std::max(0.0, t - 1.0);
  const double ramp = s < 1 ? s * s * (3 - 2 * s) : 1.0;  // smooth start
  const double yaw = 0.4 * std::sin(0.15 * s) * ramp;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(10 * std::sin(0.13 * s) * ramp, 10 * (1 - std::cos(0.13 * s)) * ramp,
                                    0.03 * std::sin(11.0 * s) * ramp);
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(0.06 * std::sin(5.5 * s) * ramp, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(0.05 * std::sin(3.1 * s) * ramp, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return T;
}

Eigen::Vector3d vee(const Eigen::Matrix3d& S) {
  return Eigen::Vector3d(S(2, 1) - S(1, 2), S(0, 2) - S(2, 0), S(1, 0) - S(0, 1)) / 2;
}

struct Recording {
  std::vector<ImuSample> imu;
  std::vector<BodyVelocitySample> velocities;
};

/// 200 Hz IMU and 10 Hz body velocities over `seconds`, from the truth's central differences;
/// `gyro_bias` added to every gyro reading, white noise of `gyro_noise` rad/s and `velocity_noise`
/// m/s; `axes` turns the IMU's readings (an IMU mounted other than described).
Recording record(double seconds, const Eigen::Vector3d& gyro_bias = Eigen::Vector3d::Zero(), double gyro_noise = 0,
                 double velocity_noise = 0, const Eigen::Matrix3d& axes = Eigen::Matrix3d::Identity()) {
  const double h = 1e-4;
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0, 1);
  Recording r;
  for (int k = 0; k <= int(seconds * 200); ++k) {
    const double t = k / 200.0;
    const Eigen::Isometry3d a = truthAt(t - h), b = truthAt(t), c = truthAt(t + h);
    const Eigen::Vector3d omega = vee(b.linear().transpose() * (c.linear() - a.linear()) / (2 * h));
    const Eigen::Vector3d acc = (c.translation() - 2 * b.translation() + a.translation()) / (h * h);
    const Eigen::Vector3d f = b.linear().transpose() * (acc + Eigen::Vector3d(0, 0, kG));
    const Eigen::Vector3d noise(n(rng), n(rng), n(rng));
    r.imu.push_back({t, axes * (omega + gyro_bias + gyro_noise * noise), axes * f});
    if (k % 20 == 0) {
      const Eigen::Vector3d v = b.linear().transpose() * (c.translation() - a.translation()) / (2 * h);
      r.velocities.push_back({t, v + velocity_noise * Eigen::Vector3d(n(rng), n(rng), n(rng)), true});
    }
  }
  return r;
}

double angleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / kPi;
}

/// Roll and pitch error: the angle between the estimate's and the truth's up in the body.
double tiltErrorDeg(const Eigen::Matrix3d& est, const Eigen::Matrix3d& truth) {
  const Eigen::Vector3d a = est.transpose() * Eigen::Vector3d::UnitZ(),
                        b = truth.transpose() * Eigen::Vector3d::UnitZ();
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180.0 / kPi;
}

}  // namespace

TEST(DopplerImu, FollowsAKnownMotionFromExactReadings) {
  const Recording r = record(60);
  const DopplerImuResult res = runDopplerImu(r.imu, r.velocities);
  ASSERT_EQ(res.trajectory.size(), r.velocities.size());
  EXPECT_TRUE(res.problems.empty()) << res.problems.front();
  double length = 0, worst_tilt = 0;
  for (std::size_t k = 0; k < res.trajectory.size(); ++k) {
    const Eigen::Isometry3d truth = truthAt(res.trajectory.stamps[k]);
    if (k) length += (truth.translation() - truthAt(res.trajectory.stamps[k - 1]).translation()).norm();
    EXPECT_LT((res.trajectory.poses[k].translation() - truth.translation()).norm(), 0.01 * length + 0.01) << k;
    EXPECT_LT(angleDeg(res.trajectory.poses[k].linear(), truth.linear()), 0.5) << k;
    worst_tilt = std::max(worst_tilt, tiltErrorDeg(res.trajectory.poses[k].linear(), truth.linear()));
  }
  EXPECT_GT(length, 50.0);
  EXPECT_LT(worst_tilt, 0.5);
}

TEST(DopplerImu, GravityHoldsRollAndPitchAgainstAGyroBias) {
  // A bias that appears after the still start (the bias taken there is zero): yaw drifts, roll and
  // pitch are held by gravity; with the gravity pull (nearly) off they drift too.
  Recording r = record(60, Eigen::Vector3d::Zero(), 0.002, 0.05);
  for (ImuSample& s : r.imu)
    if (s.t > 1.0) s.gyro += Eigen::Vector3d(0.001, -0.001, 0.001);  // 0.2 deg/s: a poor MEMS in-run bias
  const DopplerImuResult held = runDopplerImu(r.imu, r.velocities);
  DopplerImuOptions off;
  off.attitude_time_constant = 1e6;
  const DopplerImuResult free = runDopplerImu(r.imu, r.velocities, off);
  const Eigen::Isometry3d truth = truthAt(held.trajectory.stamps.back());
  const double tilt_held = tiltErrorDeg(held.trajectory.poses.back().linear(), truth.linear());
  const double tilt_free = tiltErrorDeg(free.trajectory.poses.back().linear(), truth.linear());
  EXPECT_LT(tilt_held, 1.0) << "free: " << tilt_free;
  EXPECT_GT(tilt_free, 3.0);
  // A bias present from the start is taken off.
  const Recording biased = record(30, Eigen::Vector3d(0.01, 0.02, -0.03));
  const DopplerImuResult b = runDopplerImu(biased.imu, biased.velocities);
  EXPECT_LT((b.gyro_bias - Eigen::Vector3d(0.01, 0.02, -0.03)).norm(), 1e-6);
  EXPECT_LT(angleDeg(b.trajectory.poses.back().linear(), truthAt(b.trajectory.stamps.back()).linear()), 0.5);
}

TEST(DopplerImu, AnImuWhoseGravityIsOnAnotherAxisIsSaid) {
  // The IMU's z along the body's x: gravity reads along x.
  const Eigen::Matrix3d turned = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Recording r = record(10, Eigen::Vector3d::Zero(), 0, 0, turned);
  const DopplerImuResult res = runDopplerImu(r.imu, r.velocities);
  ASSERT_FALSE(res.problems.empty());
  EXPECT_NE(res.problems.front().find("check the IMU's axes"), std::string::npos) << res.problems.front();
  EXPECT_EQ(res.trajectory.size(), r.velocities.size()) << "the run goes on";
}

TEST(DopplerImu, BadImuStreamsAreSaidWithTheirFiguresAndTheRunGoesOn) {
  Recording r = record(10);
  r.imu[100].gyro.x() = std::nan("");
  std::swap(r.imu[200], r.imu[201]);
  r.imu.push_back(r.imu[300]);                              // a time already seen
  r.imu.erase(r.imu.begin() + 1000, r.imu.begin() + 1100);  // half a second missing
  r.velocities[30].valid = false;
  const DopplerImuResult res = runDopplerImu(r.imu, r.velocities);
  std::string all;
  for (const auto& p : res.problems) all += p + "\n";
  EXPECT_NE(all.find("not in time order"), std::string::npos) << all;
  EXPECT_NE(all.find("2 IMU messages not finite or at a time already seen"), std::string::npos) << all;
  EXPECT_NE(all.find("1 gaps in the IMU longer than 0.100 s (the longest 0.505 s)"), std::string::npos) << all;
  EXPECT_EQ(res.held_velocities, 1u);
  EXPECT_EQ(res.trajectory.size(), r.velocities.size());
  EXPECT_LT((res.trajectory.poses.back().translation() - truthAt(res.trajectory.stamps.back()).translation()).norm(),
            0.2);
  EXPECT_THROW(runDopplerImu({}, r.velocities), std::invalid_argument);
  std::vector<BodyVelocitySample> none = r.velocities;
  for (auto& v : none) v.valid = false;
  EXPECT_THROW(runDopplerImu(r.imu, none), std::invalid_argument);
  DopplerImuOptions bad;
  bad.attitude_time_constant = 0;
  EXPECT_THROW(runDopplerImu(r.imu, r.velocities, bad), std::invalid_argument);
}

TEST(DopplerImu, TheRadarsLatencyIsTakenOffItsTimes) {
  Recording r = record(20);
  for (auto& v : r.velocities) v.t += 0.1;  // recorded 0.1 s late
  DopplerImuOptions o;
  o.radar_latency = 0.1;
  const DopplerImuResult res = runDopplerImu(r.imu, r.velocities, o);
  EXPECT_NEAR(res.trajectory.stamps.back(), 20.0, 1e-9);
  EXPECT_LT((res.trajectory.poses.back().translation() - truthAt(20.0).translation()).norm(), 0.1);
}

TEST(DopplerImu, TheImusPredictionRefusesAChanceDopplerConsensus) {
  // A second of scans whose Doppler consensus is a mover's (or false alarms'), each with the tight
  // covariance a good fit claims: the gate refuses them and holds the neighbours' velocity over;
  // without it they move the walk by metres. A clean walk, noise and all, loses no scan to it.
  Recording r = record(40, Eigen::Vector3d::Zero(), 0.002, 0.05);
  for (auto& v : r.velocities) v.covariance = 0.05 * 0.05 * Eigen::Matrix3d::Identity();
  const DopplerImuResult clean = runDopplerImu(r.imu, r.velocities);
  EXPECT_EQ(clean.gated_velocities, 0u);
  for (std::size_t k = 200; k < 211; ++k) r.velocities[k].velocity += Eigen::Vector3d(3.0, -2.0, 0.5);
  const DopplerImuResult gated = runDopplerImu(r.imu, r.velocities);
  DopplerImuOptions off;
  off.velocity_gate = false;
  const DopplerImuResult open = runDopplerImu(r.imu, r.velocities, off);
  const auto endError = [](const DopplerImuResult& res) {
    return (res.trajectory.poses.back().translation() - truthAt(res.trajectory.stamps.back()).translation()).norm();
  };
  EXPECT_EQ(gated.gated_velocities, 11u);
  EXPECT_EQ(gated.held_velocities, 11u);
  EXPECT_EQ(open.gated_velocities, 0u);
  std::string all;
  for (const auto& p : gated.problems) all += p + "\n";
  EXPECT_NE(all.find("11 scans' Doppler velocity beyond the IMU's prediction"), std::string::npos) << all;
  EXPECT_LT(endError(gated), 2 * endError(clean) + 0.1) << "clean " << endError(clean);
  EXPECT_GT(endError(open), 2.0);
  // A start in motion: the first velocity is taken as it is, the gate works from there.
  Recording moving = r;
  moving.imu.erase(moving.imu.begin(), moving.imu.begin() + 400);  // the IMU from t = 2 s
  const DopplerImuResult m = runDopplerImu(moving.imu, moving.velocities);
  EXPECT_EQ(m.gated_velocities, 11u);
}

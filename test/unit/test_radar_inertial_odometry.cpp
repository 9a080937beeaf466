// The 6-DoF odometry's parts (radar_ndt/odometry/inertial_filter.h, local_map_3d.h,
// radar_inertial_odometry.h): the inertial filter's still start, gyro prior, gravity and pose
// updates; the local map's frame and keyframes; the whole odometry on a simulated drive with a
// 4D radar and a MEMS IMU, radar only and fused, and its bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "radar_ndt/evaluation/metrics_6dof.h"
#include "radar_ndt/evaluation/run_report.h"
#include "radar_ndt/odometry/doppler_imu.h"
#include "radar_ndt/odometry/inertial_filter.h"
#include "radar_ndt/odometry/local_map_3d.h"
#include "radar_ndt/odometry/radar_inertial_odometry.h"
#include "radar_ndt/pipeline/inertial_run.h"
#include "radar_ndt/pipeline/run_settings.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/se3.h"
#include "radar_ndt/sim/motion_6dof.h"
#include "sanitized_build.h"

using namespace radar_ndt;

namespace {

constexpr double kG = 9.81;
constexpr double kDeg = kPi / 180;

/// `seconds` of a still IMU at 200 Hz whose body is rolled by `roll` (rad), its gyro reading `bias`.
std::vector<ImuSample> stillImu(double t0, double seconds, double roll, const Eigen::Vector3d& bias) {
  std::vector<ImuSample> imu;
  const Eigen::Matrix3d R(Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
  for (int k = 0; k <= int(seconds * 200); ++k)
    imu.push_back({t0 + k / 200.0, bias, R.transpose() * Eigen::Vector3d(0, 0, kG)});
  return imu;
}

double rollOf(const Eigen::Matrix3d& R) {
  return std::atan2(R(2, 1), R(2, 2));
}
double yawOf(const Eigen::Matrix3d& R) {
  return std::atan2(R(1, 0), R(0, 0));
}

}  // namespace

TEST(InertialFilter, AStillStartLevelsTheBodyAndTakesTheGyroBias) {
  InertialFilter f;
  std::vector<std::string> problems;
  f.initialize(stillImu(0, 1, 3 * kDeg, Eigen::Vector3d(0.002, -0.001, 0.003)), problems);
  EXPECT_TRUE(problems.empty());
  EXPECT_NEAR(rollOf(f.pose().linear()), 3 * kDeg, 1e-6);
  EXPECT_NEAR(f.gyroBias().z(), 0.003, 1e-9);
}

TEST(InertialFilter, TheGyroLessItsBiasTurnsThePrior) {
  const Eigen::Vector3d bias(0, 0, 0.01);
  InertialFilter f;
  std::vector<std::string> problems;
  f.initialize(stillImu(0, 0.5, 0, bias), problems);
  // A turn of 0.5 rad/s about the body's up for 1 s, the gyro reading it plus its bias.
  ImuSample a{1.0, Eigen::Vector3d(0, 0, 0.5) + bias, Eigen::Vector3d(0, 0, kG)};
  for (int k = 1; k <= 200; ++k) {
    ImuSample b = a;
    b.t = 1.0 + k / 200.0;
    f.predict(a, b, Eigen::Vector3d(1, 0, 0), Eigen::Matrix3d::Identity() * 1e-4, 0.1);
    a = b;
  }
  EXPECT_NEAR(yawOf(f.pose().linear()), 0.5, 1e-6);
  // Moving forward at 1 m/s while turning: the chord of the arc, along the mean heading.
  EXPECT_NEAR(f.pose().translation().norm(), 2 * std::sin(0.25) / 0.5, 1e-4);
  EXPECT_NEAR(std::atan2(f.pose().translation().y(), f.pose().translation().x()), 0.25, 1e-3);
}

TEST(InertialFilter, GravityPullsRollBackAndLeavesYaw) {
  InertialFilter f;
  std::vector<std::string> problems;
  f.initialize(stillImu(0, 0.5, 0, Eigen::Vector3d::Zero()), problems);
  // The estimate rolled 2° and turned 10° off a level body that stands still.
  Eigen::Isometry3d wrong = Eigen::Isometry3d::Identity();
  wrong.linear() =
      (Eigen::AngleAxisd(10 * kDeg, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(2 * kDeg, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  f.setPose(wrong);
  const std::vector<ImuSample> imu = stillImu(1, 10, 0, Eigen::Vector3d::Zero());
  for (std::size_t k = 1; k < imu.size(); ++k) {
    f.predict(imu[k - 1], imu[k], Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity() * 1e-4, 0.1);
    if (k % 20 == 0) {
      EXPECT_TRUE(f.updateGravity(imu[k].accel, Eigen::Vector3d::Zero()));
    }
  }
  const Eigen::Vector3d up = f.pose().linear().transpose() * Eigen::Vector3d::UnitZ();
  EXPECT_LT(std::acos(std::min(1.0, up.z())), 0.2 * kDeg) << "the body's z back to the world's up";
  EXPECT_NEAR(yawOf(f.pose().linear()), 10 * kDeg, 0.05 * kDeg) << "gravity says nothing of yaw";
  // An accelerometer far from 1 g (a shock) is not read as gravity.
  EXPECT_FALSE(f.updateGravity(Eigen::Vector3d(0, 0, 2 * kG), Eigen::Vector3d::Zero()));
}

TEST(InertialFilter, APoseUpdateMovesTheMeasuredAxesOnlyAndRefusesAFarMatch) {
  InertialFilter f;
  std::vector<std::string> problems;
  f.initialize(stillImu(0, 0.5, 0, Eigen::Vector3d::Zero()), problems);
  const std::vector<ImuSample> imu = stillImu(1, 2, 0, Eigen::Vector3d::Zero());
  for (std::size_t k = 1; k < imu.size(); ++k)
    f.predict(imu[k - 1], imu[k], Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity() * 0.01, 0.1);
  const double sigma_before = std::sqrt(f.poseCovariance()(0, 0));
  // A match 5 cm along x and 1° in yaw, as sure as the prior: about half of it is taken.
  Eigen::Isometry3d m = f.pose();
  m.translation() += Eigen::Vector3d(0.05, 0, 0);
  m.linear() = Eigen::AngleAxisd(1 * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix() * m.linear();
  Matrix6d cov = f.poseCovariance();
  cov(5, 5) = std::pow(1 * kDeg, 2);
  const Eigen::Vector3d bias = f.gyroBias();
  double distance = 0;
  ASSERT_TRUE(f.updatePose(m, cov, {true, true, true, true, true, false}, &distance));
  EXPECT_NEAR(f.pose().translation().x(), 0.025, 0.005);
  EXPECT_NEAR(yawOf(f.pose().linear()), 0.0, 1e-9) << "yaw not measured: untouched";
  EXPECT_EQ(f.gyroBias(), bias) << "a match never moves the biases";
  EXPECT_LT(std::sqrt(f.poseCovariance()(0, 0)), sigma_before);
  // A match 10 σ away is refused and leaves the state as it was.
  const Eigen::Isometry3d before = f.pose();
  Eigen::Isometry3d far = before;
  far.translation().x() += 10 * std::sqrt(f.poseCovariance()(0, 0) + cov(0, 0));
  EXPECT_FALSE(f.updatePose(far, cov, {true, true, true, true, true, true}, &distance));
  EXPECT_GT(distance, f.options().match_gate);
  EXPECT_TRUE(f.pose().isApprox(before));
}

TEST(LocalMap3D, HoldsScansInTheWorldFrameWithTheirCovariancesTurned) {
  LocalMap3DOptions o;
  o.scans = 2;
  o.distance = 0.5;
  LocalMap3D map(o);
  pcl::PointCloud<PointRadar4D> scan;
  PointRadar4D p(1, 0, 0);
  p.cov_xx = 0.04f;  // 20 cm along the body's x, 1 cm across
  p.cov_yy = p.cov_zz = 1e-4f;
  scan.push_back(p);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(10, 5, 1);
  pose.linear() = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  ASSERT_TRUE(map.wantsKeyframe(pose));
  map.add(scan, pose);
  const PointRadar4D& q = (*map.cloud())[0];
  EXPECT_NEAR(q.x, 10, 1e-5);
  EXPECT_NEAR(q.y, 6, 1e-5);
  EXPECT_NEAR(q.z, 1, 1e-5);
  EXPECT_NEAR(q.cov_yy, 0.04, 1e-6) << "the body's x is the world's y";
  EXPECT_NEAR(q.cov_xx, 1e-4, 1e-6);
  // Keyframes: not after 0.3 m, after 0.6 m; the oldest goes beyond two scans.
  Eigen::Isometry3d near = pose, next = pose;
  near.translation().x() += 0.3;
  next.translation().x() += 0.6;
  EXPECT_FALSE(map.wantsKeyframe(near));
  EXPECT_TRUE(map.wantsKeyframe(next));
  map.add(scan, next);
  next.translation().x() += 0.6;
  map.add(scan, next);
  EXPECT_EQ(map.size(), 2u);
  EXPECT_NEAR((*map.cloud())[0].x, 10.6, 1e-5);
}

// Several radars: each keeps keyframes of its own, so a second radar at the first one's pose joins
// (its view would otherwise stay out of the map), and the M kept are each radar's.
TEST(LocalMap3D, EachRadarKeepsItsOwnKeyframes) {
  LocalMap3DOptions o;
  o.scans = 2;
  LocalMap3D map(o);
  pcl::PointCloud<PointRadar4D> scan;
  scan.push_back(PointRadar4D(1, 0, 0));
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  map.add(scan, pose, 0);
  EXPECT_FALSE(map.wantsKeyframe(pose, 0));
  ASSERT_TRUE(map.wantsKeyframe(pose, 1)) << "radar 1's first scan joins where radar 0's did";
  map.add(scan, pose, 1);
  EXPECT_FALSE(map.wantsKeyframe(pose, 1));
  for (int i = 1; i <= 3; ++i) {  // radar 0 moves on: its own oldest goes, radar 1's stays
    pose.translation().x() = i;
    map.add(scan, pose, 0);
  }
  ASSERT_EQ(map.size(), 3u);
  std::vector<float> xs;
  for (const PointRadar4D& p : *map.cloud()) xs.push_back(p.x);
  EXPECT_EQ(xs, (std::vector<float>{1, 3, 4})) << "radar 1's scan at x 1, radar 0's two newest";
}

namespace {

/// A drive at 4 Hz: still 3 s, then up to about 8 m/s along a long left curve over a gentle hill.
Trajectory curveDrive(double seconds) {
  Trajectory t;
  double s_along = 0, yaw = 0;
  Eigen::Vector2d xy(0, 0);
  for (double s = 0; s <= seconds; s += 0.25) {
    const double speed = s < 3 ? 0 : 8 * std::min(1.0, (s - 3) / 5);
    s_along += speed * 0.25;
    yaw += speed * 0.25 / 80.0 * (s > 10 ? 1 : 0);
    xy += speed * 0.25 * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    const double pitch = -0.03 * std::cos(s_along / 30.0);
    T.translation() = Eigen::Vector3d(xy.x(), xy.y(), 0.9 * std::sin(s_along / 30.0));
    T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()))
                     .toRotationMatrix();
    t.stamps.push_back(50 + s);
    t.poses.push_back(T);
  }
  return t;
}

struct DriveRun {
  Trajectory trajectory;
  std::size_t fallbacks = 0, skipped = 0;
};

DriveRun runDrive(const sim::Radar4DSequence& seq, const RadarInertialOptions& o) {
  RadarInertialOdometry odometry(o);
  DriveRun r;
  std::size_t next = 0;
  for (std::size_t k = 0; k < seq.scans.size(); ++k) {
    for (; next < seq.imu.size() && seq.imu[next].t <= seq.stamps[k]; ++next) odometry.addImu(seq.imu[next]);
    const OdometryStep3D step = odometry.addScan(seq.stamps[k], seq.scans[k]);
    r.skipped += step.skipped;
    if (step.skipped) continue;
    r.fallbacks += step.fallback;
    r.trajectory.stamps.push_back(step.stamp);
    r.trajectory.poses.push_back(step.pose);
  }
  return r;
}

const sim::Radar4DSequence& driveSequence() {
  static const sim::Radar4DSequence seq = [] {
    const sim::Motion6Dof motion(curveDrive(40));
    return sim::simulateRadar4DSequence(motion, sim::worldAlongPath(motion, true, 5), sim::radar4DPreset("ars548"), 10,
                                        sim::imu6Preset("mems"), 5);
  }();
  return seq;
}

}  // namespace

TEST(RadarInertialOdometry, FusedFollowsASimulatedDriveAndHoldsTheTiltToGravity) {
  const sim::Radar4DSequence& seq = driveSequence();
  RadarInertialOptions o;
  const DriveRun fused = runDrive(seq, o);
  EXPECT_GT(fused.skipped, 0u) << "scans before the IMU's still start give no pose";
  EXPECT_LT(fused.skipped, 10u);
  EXPECT_LT(fused.fallbacks, fused.trajectory.size() / 3);
  const PosePairs pairs = associate(seq.truth, fused.trajectory);
  const AbsoluteError6Dof ate = absoluteTrajectoryError6Dof(pairs, TrajectoryAlignment::PositionYaw);
  const double length = 8 * 32 - 20;
  EXPECT_LT(ate.rmse_m, 0.005 * length) << "within 0.5 % of the path";
  // Radar only: the same pipeline without the IMU runs through, its roll and pitch unheld.
  o.use_imu = false;
  const DriveRun radar = runDrive(seq, o);
  EXPECT_EQ(radar.skipped, 0u);
  EXPECT_EQ(radar.trajectory.size(), seq.scans.size());
  const AbsoluteError6Dof ate_radar =
      absoluteTrajectoryError6Dof(associate(seq.truth, radar.trajectory), TrajectoryAlignment::PositionYaw);
  EXPECT_LT(ate_radar.rmse_m, 0.1 * length);
}

TEST(RadarInertialOdometry, BadImuAndScansAreSaidAndTheRunGoesOn) {
  const sim::Radar4DSequence& seq = driveSequence();
  RadarInertialOdometry odometry;
  // A scan before any IMU message: skipped, said.
  OdometryStep3D first = odometry.addScan(seq.stamps[0], seq.scans[0]);
  EXPECT_TRUE(first.skipped);
  EXPECT_NE(first.why.find("IMU"), std::string::npos);
  std::size_t next = 0;
  bool started = false;
  for (std::size_t k = 1; k < 80; ++k) {
    for (; next < seq.imu.size() && seq.imu[next].t <= seq.stamps[k]; ++next) {
      odometry.addImu(seq.imu[next]);
      if (next % 100 == 0) {  // a NaN message and a repeated one
        ImuSample bad = seq.imu[next];
        bad.gyro.x() = std::numeric_limits<double>::quiet_NaN();
        odometry.addImu(bad);
        odometry.addImu(seq.imu[next]);
      }
    }
    pcl::PointCloud<PointRadar4D> scan = seq.scans[k];
    if (k == 40) scan.clear();  // an empty scan
    if (k == 41) scan[0].x = std::numeric_limits<float>::quiet_NaN();
    const OdometryStep3D step = odometry.addScan(seq.stamps[k], scan);
    if (step.skipped) continue;
    started = true;
    ASSERT_TRUE(step.pose.matrix().allFinite()) << k;
    if (k == 40) {
      EXPECT_TRUE(step.fallback);
      EXPECT_FALSE(step.why.empty());
    }
  }
  EXPECT_TRUE(started);
  const std::vector<std::string> problems = odometry.problems();
  ASSERT_FALSE(problems.empty());
  EXPECT_NE(problems.back().find("dropped"), std::string::npos) << problems.back();
}

TEST(RadarInertialOdometry, SettingsAreChecked) {
  RadarInertialOptions o;
  o.method = "no-such-matcher";
  EXPECT_THROW(RadarInertialOdometry{o}, std::invalid_argument);
  o = {};
  o.min_range = 10;
  o.max_range = 5;
  EXPECT_THROW(RadarInertialOdometry{o}, std::invalid_argument);
  o = {};
  o.map.scans = 0;
  EXPECT_THROW(RadarInertialOdometry{o}, std::invalid_argument);
  o = {};
  o.filter.gravity_sigma = -1;
  EXPECT_THROW(RadarInertialOdometry{o}, std::invalid_argument);
}

// projectToPlane: a tilted pose keeps its x, y and heading (where its x axis points in the plane),
// loses z, roll and pitch; a heading is the x axis's, not the y axis's.
TEST(InertialRun, ProjectToPlaneKeepsPositionAndHeading) {
  Trajectory t;
  for (const double yaw : {0.3, 2.0, -2.8}) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(-0.15, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    T.translation() = Eigen::Vector3d(1.5, -2.0, 3.0);
    t.stamps.push_back(static_cast<double>(t.size()));
    t.poses.push_back(T);
  }
  const Trajectory p = projectToPlane(t);
  ASSERT_EQ(p.size(), t.size());
  EXPECT_EQ(p.stamps, t.stamps);
  const double yaws[] = {0.3, 2.0, -2.8};
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Pose2 q = toPose2(p.poses[i]);
    EXPECT_NEAR(q.x(), 1.5, 1e-12);
    EXPECT_NEAR(q.y(), -2.0, 1e-12);
    EXPECT_NEAR(q.z(), yaws[i], 1e-12);  // z-y-x: the yaw is the x axis's heading
    EXPECT_NEAR(p.poses[i].translation().z(), 0.0, 1e-12);
  }
  EXPECT_TRUE(isPlanar(p.poses));
}

namespace {

/// Two simulated radars on one rig as a recording's cycles: each cycle radar 0's scan (the
/// reference) and radar 1's scans since the one before, each with its mounting.
class TwoRadars : public RadarCycleSource {
 public:
  TwoRadars(const sim::Radar4DSequence& a, const Eigen::Isometry3d& mount_a, const sim::Radar4DSequence& b,
            const Eigen::Isometry3d& mount_b)
      : a_(a), b_(b), mount_{mount_a, mount_b} {}
  const std::string& sceneName() const override { return name_; }
  const std::string& referenceChannel() const override { return reference_; }
  double periodSeconds() const override { return a_.stamps[1] - a_.stamps[0]; }
  std::size_t size() const override { return a_.scans.size(); }
  std::int64_t timestamp(std::size_t k) const override { return us(a_.stamps[k]); }
  Trajectory groundTruthTrajectory() const override { return {}; }
  const std::vector<std::string>& silences() const override { return silences_; }
  RadarCycle load(std::size_t k, std::vector<std::string>*, std::size_t*) const override {
    RadarCycle cycle;
    cycle.timestamp_us = timestamp(k);
    cycle.sweeps.push_back(sweep(a_.scans[k], cycle.timestamp_us, 0));
    for (std::size_t j = 0; j < b_.scans.size(); ++j) {
      const std::int64_t t = us(b_.stamps[j]);
      if (t <= cycle.timestamp_us && (k == 0 || t > timestamp(k - 1))) cycle.sweeps.push_back(sweep(b_.scans[j], t, 1));
    }
    return cycle;
  }

 private:
  static std::int64_t us(double t) { return std::llround(t * 1e6); }
  /// As a recording reads it: PointRadar in the radar's frame, Doppler as the simulator gives it.
  RadarSweepData sweep(const pcl::PointCloud<PointRadar4D>& scan, std::int64_t t, std::uint16_t id) const {
    RadarSweepData s;
    s.timestamp_us = t;
    s.sensor_id = id;
    s.sensor_to_vehicle = mount_[id];
    for (const PointRadar4D& p : scan) {
      PointRadar q;
      q.x = p.x, q.y = p.y, q.z = p.z, q.power = p.power, q.doppler = p.doppler, q.rcs = p.rcs, q.sensor_id = id;
      s.points.push_back(q);
    }
    return s;
  }
  const sim::Radar4DSequence &a_, &b_;
  Eigen::Isometry3d mount_[2];
  std::string name_ = "two radars", reference_ = "front";
  std::vector<std::string> silences_;
};

/// The ATE (position + yaw) of `r` against `motion`.
double ateOf(const InertialRunResult& r, const sim::Motion6Dof& motion) {
  Trajectory truth;
  for (double t = motion.start(); t <= motion.end(); t += 0.01) {
    truth.stamps.push_back(t);
    truth.poses.push_back(motion.pose(t));
  }
  return absoluteTrajectoryError6Dof(associate(truth, r.estimate), TrajectoryAlignment::PositionYaw).rmse_m;
}

}  // namespace

// A rig of two radars, a forward one and one looking back from the rear: every sweep of both runs,
// each through its own mounting. Sweeps at one time are one step (their Doppler velocities fused,
// their detections matched together): better than either radar alone. At their own times (10 Hz
// and 8 Hz) each is a step, matched against the map both built: near the forward radar alone.
TEST(InertialRun, SeveralRadarsRunEachThroughItsMounting) {
  const sim::Motion6Dof motion(curveDrive(25));
  const sim::World3D world = sim::worldAlongPath(motion, true, 5);
  const sim::Imu6Options imu = sim::imu6Preset("mems");
  Eigen::Isometry3d front = Eigen::Isometry3d::Identity(), rear = Eigen::Isometry3d::Identity();
  front.translation() = Eigen::Vector3d(2.0, 0.3, 0.5);
  rear.translation() = Eigen::Vector3d(-1.0, -0.3, 0.6);
  rear.linear() = Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const sim::Radar4DModel model = sim::radar4DPreset("ars548");
  const sim::Radar4DSequence a = sim::simulateRadar4DSequence(motion, world, model, 10, imu, 5, front);
  const sim::Radar4DSequence b = sim::simulateRadar4DSequence(motion, world, model, 10, imu, 6, rear);
  const sim::Radar4DSequence none;
  InertialRunOptions o;
  o.imu = true;
  const double front_alone = ateOf(runInertialOdometry(TwoRadars(a, front, none, rear), a.imu, o), motion);
  const double rear_alone = ateOf(runInertialOdometry(TwoRadars(b, rear, none, front), a.imu, o), motion);

  const InertialRunResult together = runInertialOdometry(TwoRadars(a, front, b, rear), a.imu, o);
  EXPECT_EQ(together.radars, 2u);
  EXPECT_EQ(together.scans, a.scans.size()) << "the two sweeps of a time are one step";
  const double ate = ateOf(together, motion);
  EXPECT_LT(ate, 0.5 * std::min(front_alone, rear_alone)) << front_alone << " m and " << rear_alone << " m alone";
  EXPECT_LT(together.fallbacks, together.scans / 10);
  EXPECT_NE(summaryText(together).find("front and 1 more radar"), std::string::npos) << summaryText(together);

  if (test::kSanitizedBuild) return;  // one representative case under the sanitizers
  const sim::Radar4DSequence b8 = sim::simulateRadar4DSequence(motion, world, model, 8, imu, 6, rear);
  const InertialRunResult apart = runInertialOdometry(TwoRadars(a, front, b8, rear), a.imu, o);
  EXPECT_EQ(apart.scans, a.scans.size() + b8.scans.size()) << "each sweep at its own time, a step";
  EXPECT_LT(ateOf(apart, motion), 1.5 * front_alone);
  EXPECT_LT(ateOf(apart, motion), 0.5 * rear_alone);
}

// Each radar's detections carry its own description's spherical accuracy (the others', the
// reference's); an accuracy given as a setting is every radar's.
TEST(InertialRun, EachRadarKeepsItsOwnAccuracy) {
  SensorDescription d;
  d.radars.resize(3);
  d.radars[0].name = "front";
  d.radars[0].fields.spherical = SphericalSigmas{0.1, 0.5, 1.0};
  d.radars[1].name = "rear";
  d.radars[1].fields.spherical = SphericalSigmas{0.4, 2.0, 5.0};
  d.radars[2].name = "side";  // no accuracy of its own
  const InertialRunOptions o = inertialRunDefaults(d, "front");
  EXPECT_EQ(o.accuracyOf(0).range_sigma, 0.1);
  EXPECT_EQ(o.accuracyOf(1).range_sigma, 0.4);
  EXPECT_EQ(o.accuracyOf(1).elevation_sigma_deg, 5.0);
  EXPECT_EQ(o.accuracyOf(2).azimuth_sigma_deg, 0.5);
  const InertialRunOptions given = inertialRunOptions({{"accuracy.range_sigma", 0.3}}, o);
  for (std::uint16_t id = 0; id < 3; ++id) EXPECT_EQ(given.accuracyOf(id).range_sigma, 0.3) << id;

  // In a run, the detections handed to the step's callback (body frame) carry their radar's.
  const sim::Motion6Dof motion(curveDrive(3));
  const sim::World3D world = sim::worldAlongPath(motion, true, 5);
  Eigen::Isometry3d front = Eigen::Isometry3d::Identity(), rear = Eigen::Isometry3d::Identity();
  front.translation() = Eigen::Vector3d(2.0, 0.3, 0.5);
  rear.translation() = Eigen::Vector3d(-1.0, -0.3, 0.6);
  rear.linear() = Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const sim::Imu6Options imu = sim::imu6Preset("mems");
  const sim::Radar4DModel model = sim::radar4DPreset("ars548");
  const sim::Radar4DSequence a = sim::simulateRadar4DSequence(motion, world, model, 10, imu, 5, front);
  const sim::Radar4DSequence b = sim::simulateRadar4DSequence(motion, world, model, 10, imu, 6, rear);
  const Eigen::Isometry3d mounts[2] = {front, rear};
  std::size_t checked[2] = {0, 0};
  runInertialOdometry(
      TwoRadars(a, front, b, rear), a.imu, o, nullptr,
      [&](std::size_t, const OdometryStep3D&, const pcl::PointCloud<PointRadar4D>& body) {
        for (const PointRadar4D& p : body) {
          const Eigen::Isometry3d& m = mounts[p.sensor_id];
          const Eigen::Matrix3d R = m.linear();
          const Eigen::Matrix3d want =
              R * sphericalCovariance(m.inverse() * p.getVector3fMap().cast<double>(), o.accuracyOf(p.sensor_id)) *
              R.transpose();
          EXPECT_NEAR(p.cov_zz, want(2, 2), 1e-4 * want(2, 2) + 1e-6);
          EXPECT_NEAR(p.cov_xy, want(0, 1), 1e-4 * std::abs(want(0, 1)) + 1e-6);
          ++checked[p.sensor_id];
        }
      });
  EXPECT_GT(checked[0], 100u);
  EXPECT_GT(checked[1], 100u);
}

// The 6-DoF run (radar_ndt/pipeline/inertial_run.h): its planar projection, and a rig of several
// radars, each through its own mounting and with its own accuracy.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "drive_support.h"
#include "radar_ndt/evaluation/metrics_6dof.h"
#include "radar_ndt/evaluation/run_report.h"
#include "radar_ndt/pipeline/inertial_run.h"
#include "radar_ndt/pipeline/run_settings.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/se3.h"
#include "radar_ndt/sim/motion_6dof.h"
#include "sanitized_build.h"

using namespace radar_ndt;

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
// and 8 Hz), each a step (merge_sweeps off), matched against the map both built: within twice the
// forward radar alone; merged into the forward radar's steps, de-skewed: near the synchronised pair.
TEST(InertialRun, SeveralRadarsRunEachThroughItsMounting) {
  const sim::Motion6Dof motion(test::curveDrive(25));
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
  InertialRunOptions each_time = o;
  each_time.merge_sweeps = false;
  const InertialRunResult apart = runInertialOdometry(TwoRadars(a, front, b8, rear), a.imu, each_time);
  EXPECT_EQ(apart.scans, a.scans.size() + b8.scans.size()) << "each sweep at its own time, a step";
  EXPECT_LT(ateOf(apart, motion), 2.0 * front_alone);
  EXPECT_LT(ateOf(apart, motion), 0.5 * rear_alone);
  // Merged (the default): each cycle one step at the front radar's time, the rear's sweep de-skewed
  // to it: near the synchronised pair.
  const InertialRunResult merged = runInertialOdometry(TwoRadars(a, front, b8, rear), a.imu, o);
  EXPECT_EQ(merged.scans, a.scans.size()) << "a step a cycle";
  std::printf("front %.3f m, rear %.3f m, together %.3f m, apart %.3f m (%zu fallbacks), merged %.3f m (%zu)\n",
              front_alone, rear_alone, ate, ateOf(apart, motion), apart.fallbacks, ateOf(merged, motion),
              merged.fallbacks);
  EXPECT_LT(ateOf(merged, motion), 0.8 * ateOf(apart, motion));
  EXPECT_LT(ateOf(merged, motion), 0.5 * front_alone);
  EXPECT_LT(ateOf(merged, motion), 1.5 * ate) << "near the synchronised pair";
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
  const InertialRunOptions given = inertialRunOptions({{"accuracy.range_sigma", 0.3, ""}}, o);
  for (std::uint16_t id = 0; id < 3; ++id) EXPECT_EQ(given.accuracyOf(id).range_sigma, 0.3) << id;

  // In a run, the detections handed to the step's callback (body frame) carry their radar's.
  const sim::Motion6Dof motion(test::curveDrive(8));  // still 3 s, then 5 s moving
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

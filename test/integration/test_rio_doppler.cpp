// The real rio bag's Doppler against its IMU (part of test_rosbag): the 3D ego-velocity of
// radar_ndt/frontend/ego_velocity_3d.h with the TI preset's mounting.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Imu.h>

#include "radar_ndt/frontend/ego_velocity_3d.h"
#include "radar_ndt/frontend/point_covariance.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/odometry/doppler_imu.h"
#include "radar_ndt/odometry/radar_inertial_odometry.h"
#include "radar_ndt/pipeline/odometry_run.h"
#include "radar_ndt/ros/bag_reader.h"
#include "radar_ndt/ros/rosbag_sequence.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/sim/radar_4d.h"

using namespace radar_ndt;
namespace fs = std::filesystem;

namespace {
const std::string kRioBag = std::string(RADAR_NDT_SHARED_DATA) + "/ros-rio-ti-mmwave/ti_mmwave_rospkg_demo.bag";

/// The bag's IMU messages at their receive times (the scans' clock).
std::vector<ImuSample> readImu() {
  std::vector<ImuSample> imu;
  rosbag::Bag bag(kRioBag, rosbag::bagmode::Read);
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery("/sensor_platform/imu"))) {
    const auto msg = m.instantiate<sensor_msgs::Imu>();
    if (!msg) continue;
    imu.push_back(
        {m.getTime().toSec(),
         Eigen::Vector3d(msg->angular_velocity.x, msg->angular_velocity.y, msg->angular_velocity.z),
         Eigen::Vector3d(msg->linear_acceleration.x, msg->linear_acceleration.y, msg->linear_acceleration.z)});
  }
  return imu;
}
}  // namespace

// The 3D Doppler ego-velocity on the real rio bag, turned into the rig's frame with the TI preset's
// mounting and the gyro's lever arm: its rate of change between consecutive scans against the
// accelerometer's mean over the same interval minus its 2 s mean (gravity and slow bias), per axis,
// as docs/ros.md first measured the mounting (0.40, 0.15, 0.43). The scans' receive times lag the
// IMU's: the latency is found here as the shift that maximises the summed correlation. A wrong
// Doppler sign or mounting turns the correlations negative or sideways.
TEST(Rosbag, TheRioBagsDopplerVelocityChangesAsItsAccelerometerSays) {
  if (!fs::exists(kRioBag)) GTEST_SKIP() << "no " << kRioBag << " (../shared/data is absent)";
  const ros1::RosbagRadarSequence seq(kRioBag, readSensorDescription("preset:ti_iwr6843_rio"));
  const std::vector<ImuSample> imu = readImu();
  ASSERT_GT(imu.size(), 8000u);
  auto meanOver = [&](double t0, double t1, Eigen::Vector3d ImuSample::*field) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    for (const ImuSample& s : imu)
      if (s.t >= t0 && s.t <= t1) {
        sum += s.*field;
        ++n;
      }
    return n ? Eigen::Vector3d(sum / n) : Eigen::Vector3d(Eigen::Vector3d::Constant(std::nan("")));
  };
  const EgoVelocity3DEstimator estimator;
  std::vector<double> times;
  std::vector<Eigen::Vector3d> velocities;
  for (std::size_t k = 0; k < seq.size(); ++k) {
    const RadarCycle cycle = seq.load(k);
    const RadarSweepData& sweep = cycle.sweeps.at(0);
    const EgoVelocity3D e = estimator.estimate(sweep.points);
    if (!e.valid) continue;
    const double t = static_cast<double>(sweep.timestamp_us) * 1e-6;
    const Eigen::Vector3d omega = meanOver(t - 0.05, t + 0.05, &ImuSample::gyro);
    if (!omega.allFinite()) continue;  // before the IMU's first message
    times.push_back(t);
    velocities.push_back(bodyVelocity(sweep.sensor_to_vehicle, e.velocity, omega));
  }
  EXPECT_GT(times.size(), 400u) << "valid 3D ego-velocities with the gyro beside them, of 412 scans";
  Eigen::Vector3d mean_velocity = Eigen::Vector3d::Zero();
  for (const auto& v : velocities) mean_velocity += v / static_cast<double>(velocities.size());
  // Per axis, the correlation of the velocity's change with the accelerometer `latency` s earlier.
  auto correlations = [&](double latency) {
    std::vector<Eigen::Vector3d> dv, acc;
    for (std::size_t i = 1; i < times.size(); ++i) {
      const double dt = times[i] - times[i - 1], t0 = times[i - 1] - latency, t1 = times[i] - latency;
      if (!(dt > 0.05 && dt < 0.25)) continue;
      const Eigen::Vector3d f = meanOver(t0, t1, &ImuSample::accel) - meanOver(t1 - 1.0, t1 + 1.0, &ImuSample::accel);
      if (!f.allFinite()) continue;
      dv.push_back((velocities[i] - velocities[i - 1]) / dt);
      acc.push_back(f);
    }
    Eigen::Vector3d corr;
    const double n = static_cast<double>(dv.size());
    for (int axis = 0; axis < 3; ++axis) {
      double ma = 0, mb = 0, sab = 0, saa = 0, sbb = 0;
      for (std::size_t i = 0; i < dv.size(); ++i) {
        ma += dv[i][axis] / n;
        mb += acc[i][axis] / n;
      }
      for (std::size_t i = 0; i < dv.size(); ++i) {
        sab += (dv[i][axis] - ma) * (acc[i][axis] - mb);
        saa += std::pow(dv[i][axis] - ma, 2);
        sbb += std::pow(acc[i][axis] - mb, 2);
      }
      corr[axis] = sab / std::sqrt(saa * sbb);
    }
    return corr;
  };
  double best_latency = 0;
  Eigen::Vector3d best = correlations(0.0);
  const Eigen::Vector3d at_zero = best;
  for (int step = 1; step <= 12; ++step) {
    const Eigen::Vector3d c = correlations(0.025 * step);
    if (c.sum() > best.sum()) {
      best = c;
      best_latency = 0.025 * step;
    }
  }
  std::printf(
      "rio bag: %zu valid 3D ego-velocities, mean (%.2f, %.2f, %.2f) m/s; correlation with the "
      "accelerometer x %.2f y %.2f z %.2f at the scans' latency %.3f s (x %.2f y %.2f z %.2f without)\n",
      times.size(), mean_velocity.x(), mean_velocity.y(), mean_velocity.z(), best.x(), best.y(), best.z(), best_latency,
      at_zero.x(), at_zero.y(), at_zero.z());
  // A hand-held walk forward: along +x, not sideways.
  EXPECT_GT(mean_velocity.x(), 0.3);
  EXPECT_GT(mean_velocity.x(), 2 * std::abs(mean_velocity.y()));
  // The TI's processing and serial link: a latency of about a scan.
  EXPECT_GE(best_latency, 0.05);
  EXPECT_LE(best_latency, 0.2);
  // At least the figures docs/ros.md measured with the first fit (no latency).
  EXPECT_GE(best.x(), 0.40);
  EXPECT_GE(best.y(), 0.15);
  EXPECT_GE(best.z(), 0.43);
}

// The doppler-imu baseline on the real rio bag (no ground truth there): the walk's length, how far
// it ends from its start and how much its height wanders, with the latency found above. The
// figures docs/results/ego_velocity_3d.md quotes.
TEST(Rosbag, DopplerImuRunsOnTheRioBag) {
  if (!fs::exists(kRioBag)) GTEST_SKIP() << "no " << kRioBag << " (../shared/data is absent)";
  const ros1::RosbagRadarSequence seq(kRioBag, readSensorDescription("preset:ti_iwr6843_rio"));
  const std::vector<ImuSample> imu = readImu();
  const EgoVelocity3DEstimator estimator;
  std::vector<BodyVelocitySample> velocities;
  for (std::size_t k = 0; k < seq.size(); ++k) {
    const RadarCycle cycle = seq.load(k);
    const RadarSweepData& sweep = cycle.sweeps.at(0);
    const EgoVelocity3D e = estimator.estimate(sweep.points);
    // The lever arm's ω × t is below the Doppler's noise on this rig (a few cm from the IMU).
    velocities.push_back(
        {static_cast<double>(sweep.timestamp_us) * 1e-6, sweep.sensor_to_vehicle.linear() * e.velocity, e.valid});
  }
  DopplerImuOptions o;
  o.radar_latency = 0.125;
  const DopplerImuResult r = runDopplerImu(imu, velocities, o);
  std::string problems;
  for (const auto& p : r.problems) problems += p + "\n";
  const Trajectory& t = r.trajectory;
  ASSERT_GT(t.size(), 400u);
  double length = 0, zmin = 0, zmax = 0;
  for (std::size_t k = 1; k < t.size(); ++k) {
    length += (t.poses[k].translation() - t.poses[k - 1].translation()).norm();
    zmin = std::min(zmin, t.poses[k].translation().z());
    zmax = std::max(zmax, t.poses[k].translation().z());
  }
  const Eigen::Vector3d end = t.poses.back().translation();
  std::printf(
      "doppler-imu on the rio bag: %zu poses over %.1f s, %.1f m walked, ends (%.2f, %.2f, %.2f) m from "
      "its start, height within %.2f m; gyro bias (%.4f, %.4f, %.4f) rad/s; %zu problems\n%s",
      t.size(), t.stamps.back() - t.stamps.front(), length, end.x(), end.y(), end.z(), zmax - zmin, r.gyro_bias.x(),
      r.gyro_bias.y(), r.gyro_bias.z(), r.problems.size(), problems.c_str());
  // The IMU's z is up as the description says: nothing said about gravity.
  EXPECT_EQ(problems.find("check the IMU's axes"), std::string::npos) << problems;
  EXPECT_GT(length, 10.0);
  EXPECT_LT(length, 60.0);
}

// The 6-DoF run (radar_ndt/pipeline/inertial_run.h) on the real rio bag through the one entry as
// radar_odometry --format rosbag --method pw-ndt-3d [--imu] --radar-latency 0.125 runs it, fused and
// radar only, with the TI's accuracy. No ground truth: what the bag shows is each still stretch's
// estimated displacement (the rig does not move), the estimate's roll and pitch against the
// accelerometer's gravity at the still end, and the fallbacks.
TEST(Rosbag, RadarInertialOdometryOnTheRioBag) {
  if (!fs::exists(kRioBag)) GTEST_SKIP() << "no " << kRioBag << " (../shared/data is absent)";
  ros1::registerBagReader();
  const std::vector<ImuSample> imu = readImu();
  const SphericalAccuracy accuracy = sim::radar4DPreset("ti_iwr6843_rio").accuracy;
  for (const bool fused : {true, false}) {
    const Settings given{{"matcher.method", FieldValue(std::string("pw-ndt-3d")), ""},
                         {"imu", FieldValue(fused), ""},
                         {"radar_latency", FieldValue(0.125), ""},
                         {"accuracy.range_sigma", FieldValue(accuracy.range_sigma), ""},
                         {"accuracy.azimuth_sigma_deg", FieldValue(accuracy.azimuth_sigma_deg), ""},
                         {"accuracy.elevation_sigma_deg", FieldValue(accuracy.elevation_sigma_deg), ""}};
    const OdometryRun run({"rosbag", kRioBag, "", "", "preset:ti_iwr6843_rio"}, given);
    ASSERT_EQ(run.pipeline(), PipelineKind::Inertial);
    const InertialRunResult result = run.runInertial();
    std::vector<OdometryStep3D> steps;
    for (const OdometryStep3D& s : result.steps)
      if (!s.skipped) steps.push_back(s);
    ASSERT_GT(steps.size(), 380u);
    // Still stretches: the Doppler body speed under 5 cm/s for at least 2 s.
    std::size_t fallbacks = 0;
    for (const auto& s : steps) fallbacks += s.fallback;
    std::string stretches;
    double worst = 0;
    for (std::size_t a = 0; a < steps.size();) {
      std::size_t b = a;
      while (b < steps.size() && steps[b].velocity.norm() < 0.05) ++b;
      if (b > a && steps[b - 1].stamp - steps[a].stamp >= 2.0) {
        const double moved = (steps[b - 1].pose.translation() - steps[a].pose.translation()).norm();
        worst = std::max(worst, moved);
        char buf[96];
        std::snprintf(buf, sizeof buf, " %.1f-%.1f s: %.3f m;", steps[a].stamp - steps[0].stamp,
                      steps[b - 1].stamp - steps[0].stamp, moved);
        stretches += buf;
      }
      a = std::max(b, a + 1);
    }
    // Roll and pitch at the end against the accelerometer's mean over the last second.
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    int n = 0;
    for (const ImuSample& s : imu)
      if (s.t > imu.back().t - 1.0) f += s.accel, ++n;
    const Eigen::Vector3d up_imu = (f / n).normalized();
    const Eigen::Vector3d up_est = steps.back().pose.linear().transpose() * Eigen::Vector3d::UnitZ();
    const double tilt = std::acos(std::min(1.0, up_imu.dot(up_est))) * 180 / kPi;
    std::printf(
        "6-DoF odometry (%s) on the rio bag: %zu poses, %zu fallbacks; still stretches:%s roll/pitch at the end "
        "%.2f deg from the accelerometer's gravity\n",
        fused ? "fused" : "radar only", steps.size(), fallbacks, stretches.c_str(), tilt);
    if (fused) {  // docs/results/six_dof.md: the targets are 1° and 3 cm
      EXPECT_LT(tilt, 1.0);
      EXPECT_LT(worst, 0.03);
    }
  }
}

// Doppler ego-velocity (Kellner): exact recovery on constructed detections with moving outliers
// and agreement with ground-truth speed on real
// nuScenes sweeps (skipped without ../shared/data).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "radar_ndt/frontend/automotive_front_end.h"
#include "radar_ndt/frontend/doppler_outlier_removal.h"
#include "radar_ndt/frontend/ego_velocity.h"
#include "radar_ndt/io/nuscenes_sequence.h"
#include "radar_ndt/se2.h"

#include "doppler_support.h"

using namespace radar_ndt;

using test::makeCycle;
using test::nuScenesLikeMountings;

namespace {

/// n stationary detections of one radar at `m`, bearings within ±half_fov and 5-80 m, their
/// Doppler as the vehicle's motion `v` shows them with 5 cm/s noise; the first 30 moving (+3 m/s).
pcl::PointCloud<PointRadar> oneRadarCloud(const SensorMounting& m, const Eigen::Vector3d& v, unsigned seed, int n,
                                          double half_fov) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> az(-half_fov, half_fov), range(5.0, 80.0);
  std::normal_distribution<double> noise(0.0, 0.05);
  pcl::PointCloud<PointRadar> cloud;
  for (int i = 0; i < n; ++i) {
    const double a = az(rng), r = range(rng);
    PointRadar p(static_cast<float>(m.x + r * std::cos(a)), static_cast<float>(m.y + r * std::sin(a)), 0.f);
    p.sensor_id = 0;
    p.doppler = static_cast<float>(predictedDoppler(m, p.x, p.y, v) + noise(rng) + (i < 30 ? 3.0 : 0.0));
    cloud.push_back(p);
  }
  return cloud;
}

}  // namespace

TEST(EgoVelocity, PredictedDopplerSigns) {
  const SensorMounting front{3.4, 0.0, 0.0, true};
  // Driving forward at 10 m/s, a stationary target straight ahead approaches: −10 m/s.
  EXPECT_NEAR(predictedDoppler(front, 50.0, 0.0, Eigen::Vector3d(10, 0, 0)), -10.0, 1e-12);
  // Abeam of the sensor, no radial motion; turning left moves the front sensor left (+y).
  EXPECT_NEAR(predictedDoppler(front, 3.4, 20.0, Eigen::Vector3d(10, 0, 0)), 0.0, 1e-12);
  EXPECT_NEAR(predictedDoppler(front, 3.4, 20.0, Eigen::Vector3d(0, 0, 0.5)), -0.5 * 3.4, 1e-12);
}

TEST(EgoVelocity, RecoversVelocityWithMovingOutliers) {
  const Eigen::Vector3d v(8.0, 0.3, 0.2);
  const auto cloud = makeCycle(v, 12, 0.05, 3);  // 60 of 200 detections moving
  EgoVelocityEstimator est;
  std::vector<bool> inlier;
  const EgoVelocity e = est.estimate(cloud, nuScenesLikeMountings(), &inlier);
  ASSERT_TRUE(e.valid);
  EXPECT_NEAR(e.velocity.x(), v.x(), 0.05);
  EXPECT_NEAR(e.velocity.y(), v.y(), 0.05);
  EXPECT_NEAR(e.velocity.z(), v.z(), 0.02);
  EXPECT_EQ(std::count(inlier.begin(), inlier.end(), false), 60);
  // The covariance is positive definite and its σ are of the order of the errors.
  EXPECT_GT(e.covariance.determinant(), 0.0);
  EXPECT_LT(std::sqrt(e.covariance(0, 0)), 0.05);
  // Deterministic: the same input, the same answer to the bit.
  const EgoVelocity again = est.estimate(cloud, nuScenesLikeMountings());
  EXPECT_EQ(e.velocity, again.velocity);
}

TEST(EgoVelocity, TheLateralPriorIsWeakAgainstDetectionsThatSeeASlide) {
  // vy = 0 is observed with σ lateral_sigma (0.05 m/s) beside 140 stationary detections: a real
  // 0.3 m/s slide still comes through, a little pulled in, and vy's variance shrinks; 0 turns the
  // prior off (Kellner 2014 as published).
  const Eigen::Vector3d v(8.0, 0.3, 0.2);
  const auto cloud = makeCycle(v, 12, 0.05, 3);
  EgoVelocityOptions off;
  off.lateral_sigma = 0;
  const EgoVelocity with = EgoVelocityEstimator().estimate(cloud, nuScenesLikeMountings());
  const EgoVelocity without = EgoVelocityEstimator(off).estimate(cloud, nuScenesLikeMountings());
  ASSERT_TRUE(with.valid && without.valid);
  EXPECT_FALSE(with.nonholonomic);
  EXPECT_NEAR(without.velocity.y(), 0.3, 0.05);
  EXPECT_LT(std::abs(with.velocity.y()), std::abs(without.velocity.y()));
  EXPECT_GT(with.velocity.y(), 0.2);
  EXPECT_LT(with.covariance(1, 1), without.covariance(1, 1));
  EXPECT_NEAR(with.velocity.x(), 8.0, 0.05);
  EXPECT_NEAR(with.velocity.z(), 0.2, 0.02);
}

TEST(EgoVelocity, TooFewDetectionsIsInvalidNotACrash) {
  EgoVelocityEstimator est;
  EXPECT_FALSE(est.estimate(pcl::PointCloud<PointRadar>(), nuScenesLikeMountings()).valid);
  auto cloud = makeCycle(Eigen::Vector3d(5, 0, 0), 0, 0.05, 1);
  cloud.resize(4);
  EXPECT_FALSE(est.estimate(cloud, nuScenesLikeMountings()).valid);
  // Points of a sensor without a mounting are ignored.
  auto unknown = makeCycle(Eigen::Vector3d(5, 0, 0), 0, 0.05, 1);
  for (auto& p : unknown) p.sensor_id = 9;
  EXPECT_FALSE(est.estimate(unknown, nuScenesLikeMountings()).valid);
}

TEST(EgoVelocity, OneRadarFallsBackToTheNonholonomicModel) {
  // One radar sees only its own velocity: (vx, vy, ω) is unobservable, and the full model must say
  // so rather than guess. With vy = 0 at the vehicle origin (Kellner 2013), (vx, ω) is recovered.
  const SensorMounting front{3.41, 0.0, 0.0, true};
  const Eigen::Vector3d v(8.0, 0.0, 0.2);
  const pcl::PointCloud<PointRadar> cloud = oneRadarCloud(front, v, 5, 120, 0.8);
  EgoVelocityEstimator est;
  std::vector<bool> inlier;
  const EgoVelocity e = est.estimate(cloud, {front}, &inlier);
  ASSERT_TRUE(e.valid);
  EXPECT_TRUE(e.nonholonomic);
  EXPECT_NEAR(e.velocity.x(), 8.0, 0.05);
  EXPECT_EQ(e.velocity.y(), 0.0);
  EXPECT_NEAR(e.velocity.z(), 0.2, 0.02);
  EXPECT_NEAR(std::sqrt(e.covariance(1, 1)), est.options().lateral_sigma, 1e-12);
  EXPECT_EQ(e.covariance(0, 1), 0.0);
  EXPECT_GT(e.covariance(2, 2), 0.0);
  for (int i = 0; i < 30; ++i) EXPECT_FALSE(inlier[static_cast<std::size_t>(i)]) << i;

  EgoVelocityOptions full;
  full.model = EgoVelocityModel::Full;
  EXPECT_FALSE(EgoVelocityEstimator(full).estimate(cloud, {front}).valid) << "one radar place cannot give (vx, vy, ω)";
  // Radars at several places keep the full model, and recover a sideways velocity it allows.
  const Eigen::Vector3d slide(8.0, 0.3, 0.2);
  const EgoVelocity f = est.estimate(makeCycle(slide, 0, 0.05, 3), nuScenesLikeMountings());
  EXPECT_FALSE(f.nonholonomic);
  EXPECT_NEAR(f.velocity.y(), 0.3, 0.05);
}

TEST(EgoVelocity, ARadarOnTheRearAxleLineGivesTheForwardSpeedAlone) {
  // At mx = 0 (Snail-Radar's ARS548 at the base frame's origin) the nonholonomic rows' ω column is
  // the vx column times −my: the radar sees vx − ω my and nothing of ω. The fit must give that
  // speed, valid, with ω unknown, rather than refuse every cycle.
  const Eigen::Vector3d v(8.0, 0.0, 0.2);
  for (const double my : {0.0, 0.6}) {
    const SensorMounting radar{0.05, my, -0.05, true};
    const pcl::PointCloud<PointRadar> cloud = oneRadarCloud(radar, v, 7, 150, 1.0);
    std::vector<bool> inlier;
    const EgoVelocity e = EgoVelocityEstimator().estimate(cloud, {radar}, &inlier);
    ASSERT_TRUE(e.valid) << "my " << my;
    EXPECT_TRUE(e.nonholonomic && e.forward_only);
    EXPECT_NEAR(e.velocity.x(), v.x() - v.z() * my, 0.05) << "my " << my;
    EXPECT_EQ(e.velocity.y(), 0.0);
    EXPECT_EQ(e.velocity.z(), 0.0);
    EXPECT_NEAR(e.covariance(2, 2), 1.0, 1e-12) << "ω unknown";
    EXPECT_NEAR(e.covariance(0, 2), my, 1e-12) << "vx = u + ω my";
    EXPECT_LT(e.covariance(0, 0) - my * my, 1e-3);
    for (int i = 0; i < 30; ++i) EXPECT_FALSE(inlier[static_cast<std::size_t>(i)]) << i;
  }
  // Off the axle's line the yaw rate is fitted as before.
  const SensorMounting off{0.5, 0.0, 0.0, true};
  pcl::PointCloud<PointRadar> cloud;
  for (int i = 0; i < 60; ++i) {
    const double a = -1.0 + i / 30.0;
    PointRadar p(static_cast<float>(off.x + 20 * std::cos(a)), static_cast<float>(20 * std::sin(a)), 0.f);
    p.sensor_id = 0;
    p.doppler = static_cast<float>(predictedDoppler(off, p.x, p.y, v));
    cloud.push_back(p);
  }
  const EgoVelocity e = EgoVelocityEstimator().estimate(cloud, {off});
  ASSERT_TRUE(e.valid);
  EXPECT_FALSE(e.forward_only);
  EXPECT_NEAR(e.velocity.z(), 0.2, 1e-3);
}

TEST(EgoVelocity, RealSweepsAgreeWithGroundTruthSpeed) {
  // All radars of each cycle (the full model), and the front radar alone (the nonholonomic one).
  const std::string root = std::string(RADAR_NDT_SHARED_DATA) + "/nuscenes-mini-radar";
  if (!std::filesystem::exists(root + "/v1.0-mini/sensor.json"))
    GTEST_SKIP() << "no " << root << ": skipping the real-data check";
  const NuScenesDataset ds(root);
  const AutomotiveFrontEnd fe;
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  for (const auto& scene : ds.scenes()) {
    const NuScenesRadarSequence seq(ds, scene, NuScenesSequenceOptions{});
    std::vector<double> err, one_speed_err, one_rate_err;
    for (std::size_t k = 1; k + 1 < seq.size(); ++k) {
      // Ground truth: central differences of the ego poses around cycle k.
      const double dt = 1e-6 * static_cast<double>(seq.timestamp(k + 1) - seq.timestamp(k - 1));
      const Pose2 a = toPose2(seq.groundTruth(k - 1)), b = toPose2(seq.groundTruth(k + 1));
      const double speed = (b.head<2>() - a.head<2>()).norm() / dt, rate = normalizeAngle(b.z() - a.z()) / dt;
      RadarCycle cycle = seq.load(k);
      const ProcessedCycle c = fe.process(cycle);
      if (c.ego.valid) err.push_back(std::abs(c.ego.velocity.head<2>().norm() - speed));
      cycle.sweeps.erase(std::remove_if(cycle.sweeps.begin(), cycle.sweeps.end(),
                                        [&](const RadarSweepData& s) { return s.timestamp_us != cycle.timestamp_us; }),
                         cycle.sweeps.end());
      ASSERT_EQ(cycle.sweeps.size(), 1u);
      const ProcessedCycle one = fe.process(cycle);
      if (!one.ego.valid) continue;
      EXPECT_TRUE(one.ego.nonholonomic);
      one_speed_err.push_back(std::abs(one.ego.velocity.head<2>().norm() - speed));
      one_rate_err.push_back(std::abs(one.ego.velocity.z() - rate));
    }
    ASSERT_GT(err.size(), seq.size() / 2) << scene.name;
    ASSERT_GT(one_speed_err.size(), seq.size() * 3 / 4) << scene.name;
    EXPECT_LT(median(err), 0.3) << scene.name;
    // One radar, measured: 0.066-0.089 m/s and 0.013-0.039 rad/s (all five: 0.008-0.039 rad/s, the
    // same 0.025-0.039 on 0796 and 1077, whose ground truth turns less than every method).
    EXPECT_LT(median(one_speed_err), 0.3) << scene.name;
    EXPECT_LT(median(one_rate_err), 0.05) << scene.name;
    std::printf("%s: median |speed error| %.3f m/s; front radar alone %.3f m/s, |yaw-rate error| %.4f rad/s\n",
                scene.name.c_str(), median(err), median(one_speed_err), median(one_rate_err));
  }
}

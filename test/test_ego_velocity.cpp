// Doppler ego-velocity (Kellner): exact recovery on constructed detections with moving outliers,
// the PCL filter that removes them, cycle planning, and agreement with ground-truth speed on real
// nuScenes sweeps (skipped without ../shared/data).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "radar_ndt/doppler_outlier_removal.h"
#include "radar_ndt/ego_velocity.h"
#include "radar_ndt/nuscenes_sequence.h"
#include "radar_ndt/radar_cycle.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;

namespace {

std::vector<SensorMounting> nuScenesLikeMountings() {
  return {{3.41, 0.0, 0.0, true}, {2.42, 0.8, M_PI / 2, true}, {2.42, -0.8, -M_PI / 2, true}, {-0.56, 0.63, M_PI, true},
          {-0.56, -0.62, -M_PI, true}};
}

/// Stationary detections around the car seen with velocity v, plus `movers` detections with a
/// Doppler 3 m/s off; Gaussian Doppler noise σ.
pcl::PointCloud<PointRadar> makeCycle(const Eigen::Vector3d& v, int movers, double sigma, std::uint32_t seed) {
  const auto mounts = nuScenesLikeMountings();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> az(-1.0, 1.0), range(5.0, 80.0);
  std::normal_distribution<double> noise(0.0, sigma);
  pcl::PointCloud<PointRadar> cloud;
  for (std::uint16_t s = 0; s < mounts.size(); ++s) {
    for (int i = 0; i < 40; ++i) {
      const double a = mounts[s].yaw + az(rng), r = range(rng);
      PointRadar p(static_cast<float>(mounts[s].x + r * std::cos(a)), static_cast<float>(mounts[s].y + r * std::sin(a)), 0.f);
      p.sensor_id = s;
      p.doppler = static_cast<float>(predictedDoppler(mounts[s], p.x, p.y, v) + noise(rng) + (i < movers ? 3.0 : 0.0));
      cloud.push_back(p);
    }
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

TEST(DopplerOutlierRemoval, IsAPclFilterWithNegative) {
  const Eigen::Vector3d v(6.0, 0.0, -0.1);
  const auto cloud = makeCycle(v, 10, 0.03, 5).makeShared();
  DopplerOutlierRemoval<PointRadar> f;
  f.setInputCloud(cloud);
  f.setEgoVelocity(v);
  f.setMountings(nuScenesLikeMountings());
  pcl::PointCloud<PointRadar> kept, removed;
  f.filter(kept);
  f.setNegative(true);
  f.filter(removed);
  EXPECT_EQ(kept.size(), 150u);
  EXPECT_EQ(removed.size(), 50u);
  for (const auto& p : removed) EXPECT_GT(std::abs(p.doppler - predictedDoppler(nuScenesLikeMountings()[p.sensor_id], p.x, p.y, v)), 2.0);
  // Through the base class, as PCL users compose filters.
  pcl::Filter<PointRadar>::Ptr base = pcl::make_shared<DopplerOutlierRemoval<PointRadar>>(f);
  pcl::PointCloud<PointRadar> again;
  base->filter(again);
  EXPECT_EQ(again.size(), 50u);
}

TEST(RadarCycles, ReferenceClocksAndOthersWithinOnePeriod) {
  // Channel 0 every 100 ms; channel 1 offset by 30 ms; channel 2 missing for a while.
  std::vector<SweepStamp> s;
  for (int k = 0; k < 10; ++k) {
    s.push_back({k * 100000, 0});
    s.push_back({k * 100000 + 30000, 1});
    if (k < 3 || k > 6) s.push_back({k * 100000 + 60000, 2});
  }
  std::sort(s.begin(), s.end(), [](const SweepStamp& a, const SweepStamp& b) { return a.timestamp_us < b.timestamp_us; });
  const auto plans = planRadarCycles(s, 0);
  ASSERT_EQ(plans.size(), 10u);
  EXPECT_EQ(plans[0].members.size(), 1u);  // nothing before the first reference sweep
  for (std::size_t k = 1; k < plans.size(); ++k) {
    const std::int64_t t = s[plans[k].reference].timestamp_us;
    for (const auto m : plans[k].members) {
      EXPECT_LE(s[m].timestamp_us, t);
      EXPECT_GT(s[m].timestamp_us, t - 100000);
    }
    const bool has2 = (k - 1 < 3 || k - 1 > 6);
    EXPECT_EQ(plans[k].members.size(), has2 ? 3u : 2u) << k;
  }
}

TEST(EgoVelocity, RealSweepsAgreeWithGroundTruthSpeed) {
  const std::string root = std::string(RADAR_NDT_SHARED_DATA) + "/nuscenes-mini-radar";
  if (!std::filesystem::exists(root + "/v1.0-mini/sensor.json")) GTEST_SKIP() << "no " << root << ": skipping the real-data check";
  const NuScenesDataset ds(root);
  const AutomotiveFrontEnd fe;
  for (const auto& scene : ds.scenes()) {
    const NuScenesRadarSequence seq(ds, scene, NuScenesRadarSequence::Options{});
    std::vector<double> err;
    for (std::size_t k = 1; k + 1 < seq.size(); ++k) {
      const ProcessedCycle c = fe.process(seq.load(k));
      if (!c.ego.valid) continue;
      // Ground-truth speed: central difference of the ego positions around cycle k.
      const double dt = 1e-6 * static_cast<double>(seq.timestamp(k + 1) - seq.timestamp(k - 1));
      const double speed = (seq.groundTruth(k + 1).translation() - seq.groundTruth(k - 1).translation()).head<2>().norm() / dt;
      err.push_back(std::abs(c.ego.velocity.head<2>().norm() - speed));
    }
    ASSERT_GT(err.size(), seq.size() / 2) << scene.name;
    std::nth_element(err.begin(), err.begin() + static_cast<std::ptrdiff_t>(err.size() / 2), err.end());
    EXPECT_LT(err[err.size() / 2], 0.3) << scene.name;
    RecordProperty("median_speed_error_" + scene.name, std::to_string(err[err.size() / 2]));
  }
}

// The 3D Doppler ego-velocity (radar_ndt/frontend/ego_velocity_3d.h): synthetic scans with moving
// detections, the simulator's presets (the error table of docs/results/ego_velocity_3d.md), the
// mounting's lever arm, degenerate scans.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "radar_ndt/frontend/ego_velocity_3d.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/sim/radar_4d.h"

using namespace radar_ndt;

namespace {

struct Scan {
  std::vector<Eigen::Vector3d> positions;
  std::vector<double> doppler;
  std::vector<bool> moving;
};

/// Detections within ±60° azimuth and ±`elevation_deg`, 1-50 m, Doppler noise σ; a share of them
/// on moving objects (their own radial velocity added, 0.5-5 m/s either way).
Scan syntheticScan(const Eigen::Vector3d& v, std::size_t n, double moving_share, double sigma, double elevation_deg,
                   unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> az(-kPi / 3, kPi / 3),
      el(-elevation_deg * kPi / 180, elevation_deg * kPi / 180), range(1, 50), speed(0.5, 5), unit(0, 1);
  std::normal_distribution<double> noise(0, sigma);
  Scan s;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = az(rng), e = el(rng), r = range(rng);
    const Eigen::Vector3d p(r * std::cos(e) * std::cos(a), r * std::cos(e) * std::sin(a), r * std::sin(e));
    double d = predictedDoppler3D(p, v) + noise(rng);
    const bool moving = unit(rng) < moving_share;
    if (moving) d += (unit(rng) < 0.5 ? -1 : 1) * speed(rng);
    s.positions.push_back(p);
    s.doppler.push_back(d);
    s.moving.push_back(moving);
  }
  return s;
}

double mahalanobis(const EgoVelocity3D& e, const Eigen::Vector3d& truth) {
  const Eigen::Vector3d d = e.velocity - truth;
  return std::sqrt(d.dot(e.covariance.inverse() * d));
}

}  // namespace

TEST(EgoVelocity3D, AStaticPointAheadApproachesARadarMovingForward) {
  // Positive receding: driving towards a point ahead, its Doppler is negative.
  EXPECT_DOUBLE_EQ(predictedDoppler3D(Eigen::Vector3d(10, 0, 0), Eigen::Vector3d(2, 0, 0)), -2.0);
  EXPECT_DOUBLE_EQ(predictedDoppler3D(Eigen::Vector3d(0, 0, 5), Eigen::Vector3d(0, 0, -1)), 1.0);
}

TEST(EgoVelocity3D, RecoversTheVelocityAndFlagsTheMovingDetections) {
  const Eigen::Vector3d truth(1.2, -0.3, 0.25);
  const Scan s = syntheticScan(truth, 200, 0.3, 0.05, 15, 7);
  std::vector<bool> inlier;
  const EgoVelocity3D e = EgoVelocity3DEstimator().estimate(s.positions, s.doppler, &inlier);
  ASSERT_TRUE(e.valid) << e.why;
  EXPECT_LT((e.velocity - truth).norm(), 0.05) << e.velocity.transpose();
  EXPECT_LT(mahalanobis(e, truth), 4.0);
  EXPECT_NEAR(e.residual_rms, 0.05, 0.02);
  ASSERT_EQ(inlier.size(), s.positions.size());
  std::size_t wrong = 0, moving = 0;
  for (std::size_t i = 0; i < inlier.size(); ++i) {
    moving += s.moving[i];
    // A moving detection whose own motion is within the threshold is indistinguishable: count only
    // those clearly moving (all are: 0.5 m/s or more against a 0.2 m/s threshold).
    wrong += inlier[i] == s.moving[i];
  }
  EXPECT_GT(moving, 40u);
  EXPECT_LE(wrong, 4u);
  EXPECT_EQ(e.inliers, static_cast<std::size_t>(std::count(inlier.begin(), inlier.end(), true)));
}

TEST(EgoVelocity3D, TheCovarianceCoversTheErrorOverManyScans) {
  // Over 200 scans the squared Mahalanobis distance of a consistent covariance averages 3 (χ², 3 dof).
  const Eigen::Vector3d truth(0.8, 0.4, -0.1);
  double sum = 0;
  for (unsigned k = 0; k < 200; ++k) {
    const Scan s = syntheticScan(truth, 60, 0.2, 0.08, 20, 100 + k);
    const EgoVelocity3D e = EgoVelocity3DEstimator().estimate(s.positions, s.doppler);
    ASSERT_TRUE(e.valid) << k << ": " << e.why;
    sum += std::pow(mahalanobis(e, truth), 2);
  }
  EXPECT_GT(sum / 200, 1.5);
  EXPECT_LT(sum / 200, 6.0);
}

TEST(EgoVelocity3D, DegenerateScansAreInvalidAndSayWhy) {
  const EgoVelocity3DEstimator est;
  // A planar radar's detections: no elevation, so the vertical velocity is unobserved.
  Scan flat = syntheticScan(Eigen::Vector3d(1, 0, 0), 100, 0, 0.03, 0, 3);
  EgoVelocity3D e = est.estimate(flat.positions, flat.doppler);
  EXPECT_FALSE(e.valid);
  EXPECT_FALSE(e.why.empty());
  // Too few detections, NaN and too near ones left out.
  Scan few = syntheticScan(Eigen::Vector3d(1, 0, 0), 4, 0, 0.03, 15, 4);
  few.positions.push_back(Eigen::Vector3d(std::numeric_limits<double>::quiet_NaN(), 0, 0));
  few.doppler.push_back(0);
  few.positions.push_back(Eigen::Vector3d(0.1, 0, 0));
  few.doppler.push_back(0);
  e = est.estimate(few.positions, few.doppler);
  EXPECT_FALSE(e.valid);
  EXPECT_EQ(e.points, 4u);
  EXPECT_NE(e.why.find("usable detections"), std::string::npos) << e.why;
  // A scene that is mostly moving: the static share is below min_inlier_ratio.
  Scan busy = syntheticScan(Eigen::Vector3d(1, 0, 0), 100, 0.95, 0.03, 15, 5);
  e = est.estimate(busy.positions, busy.doppler);
  EXPECT_FALSE(e.valid);
  // Empty; and mismatched lengths.
  EXPECT_FALSE(est.estimate(std::vector<Eigen::Vector3d>{}, std::vector<double>{}).valid);
  EXPECT_FALSE(est.estimate(few.positions, std::vector<double>(2, 0.0)).valid);
  EgoVelocity3DOptions bad;
  bad.inlier_threshold = -1;
  EXPECT_THROW(EgoVelocity3DEstimator{bad}, std::invalid_argument);
}

// A lorry filling the view: its detections (one rigid motion, so one consistent velocity) outnumber
// the static world's. RANSAC alone takes the lorry; a prediction of the radar's velocity (an
// IMU's) keeps it to the static world, and a prediction no consensus agrees with is refused.
TEST(EgoVelocity3D, APredictionKeepsTheStaticWorldWhenAMoverFillsTheView) {
  const Eigen::Vector3d truth(8, 0.2, 0), lorry_relative(-6, 0.5, 0);
  Scan s = syntheticScan(truth, 40, 0, 0.05, 15, 21);
  const Scan lorry = syntheticScan(truth - lorry_relative, 90, 0, 0.05, 15, 22);
  for (std::size_t i = 0; i < lorry.positions.size(); ++i) {
    s.positions.push_back(lorry.positions[i]);
    s.doppler.push_back(lorry.doppler[i]);
    s.moving.push_back(true);
  }
  const EgoVelocity3DEstimator est;
  const EgoVelocity3D alone = est.estimate(s.positions, s.doppler);
  ASSERT_TRUE(alone.valid) << alone.why;
  EXPECT_GT((alone.velocity - truth).norm(), 3.0) << "without a prediction the lorry wins";

  EgoVelocityPrior prior;
  prior.velocity = truth + Eigen::Vector3d(0.15, -0.1, 0.05);
  prior.covariance = 0.2 * 0.2 * Eigen::Matrix3d::Identity();
  std::vector<bool> inlier;
  const EgoVelocity3D guided = est.estimate(s.positions, s.doppler, &inlier, &prior);
  ASSERT_TRUE(guided.valid) << guided.why;
  EXPECT_LT((guided.velocity - truth).norm(), 0.1) << guided.velocity.transpose();
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < inlier.size(); ++i) wrong += inlier[i] == s.moving[i];
  EXPECT_LE(wrong, 3u);

  // Only the lorry in view, the prediction the static world's: refused, and the flags are the
  // prediction's (no lorry detection among them).
  const EgoVelocity3D refused = est.estimate(lorry.positions, lorry.doppler, &inlier, &prior);
  EXPECT_FALSE(refused.valid);
  EXPECT_FALSE(refused.why.empty());
  EXPECT_EQ(std::count(inlier.begin(), inlier.end(), true), 0);
  // A prediction with room for the lorry's velocity takes it: the gate is the prediction's.
  prior.covariance = 10.0 * 10.0 * Eigen::Matrix3d::Identity();
  EXPECT_TRUE(est.estimate(lorry.positions, lorry.doppler, nullptr, &prior).valid);
}

TEST(EgoVelocity3D, TheSameScanGivesTheSameAnswer) {
  const Scan s = syntheticScan(Eigen::Vector3d(3, 0, 0), 80, 0.3, 0.05, 15, 9);
  const EgoVelocity3D a = EgoVelocity3DEstimator().estimate(s.positions, s.doppler);
  const EgoVelocity3D b = EgoVelocity3DEstimator().estimate(s.positions, s.doppler);
  EXPECT_TRUE(a.velocity == b.velocity);
}

TEST(EgoVelocity3D, TheBodysVelocityAddsTheLeverArm) {
  // A rig turning about its z at 1 rad/s, standing still at its origin: a radar 0.5 m ahead moves
  // sideways at 0.5 m/s; bodyVelocity() takes that back out.
  Eigen::Isometry3d radar_to_body = Eigen::Isometry3d::Identity();
  radar_to_body.translation() = Eigen::Vector3d(0.5, 0, 0);
  radar_to_body.linear() = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d omega(0, 0, 1);
  // The radar's velocity in body axes is (0, 0.5, 0); in radar axes (turned 90° about z): (0.5, 0, 0).
  const Eigen::Vector3d radar_velocity(0.5, 0, 0);
  EXPECT_LT(bodyVelocity(radar_to_body, radar_velocity, omega).norm(), 1e-12);
  const Eigen::Matrix3d c = bodyVelocityCovariance(radar_to_body, Eigen::Vector3d(1, 2, 3).asDiagonal());
  EXPECT_NEAR(c(0, 0), 2, 1e-12);
  EXPECT_NEAR(c(1, 1), 1, 1e-12);
}

// Each preset of the 4D simulator on its own world: a car along the street for the car radars, a
// walk through the corridors for the TI. The table docs/results/ego_velocity_3d.md quotes.
TEST(EgoVelocity3D, SimulatedScansOfEachPreset) {
  std::printf("| preset | scans | valid | median error (m/s) | 90th percentile (m/s) | median inliers |\n");
  for (const std::string& preset : sim::radar4DPresetNames()) {
    const bool handheld = preset == "ti_iwr6843_rio";
    const sim::World3D world = handheld ? sim::corridorWorld(11) : sim::streetWorld(300, 11);
    const sim::Radar4DModel model = sim::radar4DPreset(preset);
    const double speed = handheld ? 1.2 : 10.0;
    std::vector<double> errors, inliers;
    const int scans = 40;
    for (int k = 0; k < scans; ++k) {
      // Along x with a sway: the velocity has all three components in the sensor frame.
      const double t = 0.1 * k;
      Pose3 pose = Pose3::Identity();
      pose.translation() = handheld ? Eigen::Vector3d(-10 + speed * t, 0.5, 1.4) : Eigen::Vector3d(speed * t, 0, 1.0);
      pose.linear() = (Eigen::AngleAxisd(0.15 * std::sin(t), Eigen::Vector3d::UnitZ()) *
                       Eigen::AngleAxisd(0.08 * std::sin(2 * t), Eigen::Vector3d::UnitY()))
                          .toRotationMatrix();
      const Eigen::Vector3d v_world(speed, 0.1 * speed * std::cos(t), 0.05 * speed);
      const auto scan = sim::simulateScan4D(world, pose, v_world, model, 5, k);
      const EgoVelocity3D e = EgoVelocity3DEstimator().estimate(scan);
      if (!e.valid) continue;
      errors.push_back((e.velocity - pose.linear().transpose() * v_world).norm());
      inliers.push_back(static_cast<double>(e.inliers));
    }
    ASSERT_GE(errors.size(), 36u) << preset;
    auto quantile = [](std::vector<double> x, double q) {
      std::sort(x.begin(), x.end());
      return x[static_cast<std::size_t>(q * static_cast<double>(x.size() - 1))];
    };
    const double median = quantile(errors, 0.5);
    std::printf("| %s | %d | %zu | %.3f | %.3f | %.0f |\n", preset.c_str(), scans, errors.size(), median,
                quantile(errors, 0.9), quantile(inliers, 0.5));
    // A few times the Doppler noise over √(inliers): a sign or geometry error is metres a second.
    EXPECT_LT(median, 4 * model.doppler_sigma) << preset;
  }
}

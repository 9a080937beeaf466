// AutomotiveOdometry::add: failure handling on a constructed bad
// matcher, dead reckoning, skipped timestamps and stale ego-velocities.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "radar_ndt/odometry/automotive_odometry.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;

namespace {

/// A matcher that always "converges" to a 2 m sideways jump: what a match onto a passing truck
/// can look like.
class JumpingMatcher : public RadarRegistration {
 public:
  JumpingMatcher() { reg_name_ = "JumpingMatcher"; }
  int calls = 0;
  std::vector<double> grids;  ///< the grid of each align(): ICP's max correspondence distance here

 protected:
  void computeTransformation(PointCloudSource& output, const Eigen::Matrix4f& guess) override {
    ++calls;
    grids.push_back(getMaxCorrespondenceDistance());
    final_transformation_ = guess;
    final_transformation_(1, 3) += 2.0f;
    pcl::transformPointCloud(*input_, output, final_transformation_);
    converged_ = true;
  }
};

/// A matcher that "converges" at its initial guess: one that adds no information.
class GuessMatcher : public RadarRegistration {
 public:
  GuessMatcher() { reg_name_ = "GuessMatcher"; }

 protected:
  void computeTransformation(PointCloudSource& output, const Eigen::Matrix4f& guess) override {
    final_transformation_ = guess;
    pcl::transformPointCloud(*input_, output, final_transformation_);
    converged_ = true;
  }
};

/// Returns its guess and keeps the power of every source point it was given, per align().
class PowerRecorder : public RadarRegistration {
 public:
  std::vector<std::vector<float>> source_power, target_power;

 protected:
  void computeTransformation(PointCloudSource& output, const Eigen::Matrix4f& guess) override {
    std::vector<float> s, t;
    for (const auto& p : *input_) s.push_back(p.power);
    for (const auto& p : *target_) t.push_back(p.power);
    source_power.push_back(s);
    target_power.push_back(t);
    final_transformation_ = guess;
    pcl::transformPointCloud(*input_, output, final_transformation_);
    converged_ = true;
  }
};

/// Every cycle's first attempt runs at this grid.
constexpr double kGrid = 3.0;

/// A test matcher driven from kGrid.
template <typename R>
MatcherAdapter atNominalGrid(const std::shared_ptr<R>& r) {
  return MatcherAdapter(r, MatchSettings{kGrid, 0.f});
}

ProcessedCycle constantCycle(std::int64_t t_us, const Eigen::Vector3d& v) {
  ProcessedCycle c;
  c.timestamp_us = t_us;
  for (int i = 0; i < 50; ++i) {
    PointRadar p(static_cast<float>(5 + i), static_cast<float>((i % 7) - 3), 0.f);
    p.cov_xx = p.cov_yy = 0.01f;
    c.cloud->push_back(p);
  }
  c.ego.velocity = v;
  c.ego.covariance = Eigen::Matrix3d::Identity() * 1e-4;
  c.ego.valid = true;
  return c;
}

}  // namespace

TEST(AutomotiveOdometry, ImplausibleMatchesAreRetriedThenFallBackToDoppler) {
  auto matcher = pcl::make_shared<JumpingMatcher>();
  AutomotiveOdometryOptions o;
  AutomotiveOdometry odo(o, atNominalGrid(matcher));
  const Eigen::Vector3d v(10.0, 0.0, 0.0);
  for (int k = 0; k < 5; ++k) odo.add(constantCycle(k * 75000, v));
  EXPECT_EQ(odo.counters().fallbacks, 4u);
  EXPECT_EQ(matcher->calls, 4 * (o.max_retries + 1));
  // Each retry enlarges the grid by grid_step; the next cycle starts at the nominal grid again.
  ASSERT_EQ(matcher->grids.size(), static_cast<std::size_t>(matcher->calls));
  for (std::size_t i = 0; i < matcher->grids.size(); ++i) {
    const auto attempt = static_cast<double>(i % static_cast<std::size_t>(o.max_retries + 1));
    EXPECT_NEAR(matcher->grids[i], kGrid + o.grid_step * attempt, 1e-9) << "align " << i;
  }
  EXPECT_NEAR(odo.steps().back().grid, kGrid + o.grid_step * o.max_retries, 1e-9);
  const auto& last = odo.steps().back();
  EXPECT_EQ(last.status, StepStatus::Fallback);
  EXPECT_NEAR(last.pose.x(), 4 * 0.75, 1e-9);  // the Doppler integral, not the jumps
  EXPECT_NEAR(last.pose.y(), 0.0, 1e-9);
  // Without the gate the jumps are accepted: in the paper's mode they are the motion (what plain
  // submap matching does); fused, each pulls the motion part of the way, by the covariances.
  o.gate.enabled = false;
  AutomotiveOdometry ungated(o.paper(3), atNominalGrid(pcl::make_shared<JumpingMatcher>()));
  for (int k = 0; k < 5; ++k) ungated.add(constantCycle(k * 75000, v));
  EXPECT_EQ(ungated.counters().fallbacks, 0u);
  EXPECT_NEAR(ungated.steps().back().pose.y(), 8.0, 1e-4);
  AutomotiveOdometry fused(o, atNominalGrid(pcl::make_shared<JumpingMatcher>()));
  for (int k = 0; k < 5; ++k) fused.add(constantCycle(k * 75000, v));
  EXPECT_EQ(fused.counters().fallbacks, 0u);
  EXPECT_GT(fused.steps().back().pose.y(), 0.01);
  EXPECT_LT(fused.steps().back().pose.y(), 1.0);
}

TEST(AutomotiveOdometry, AGuessReturningMatcherAddsNothingToTheDopplerIntegral) {
  // In either mode: the fusion sees no innovation, learns no bias, and the poses are the Doppler
  // integral's (up to the float guess the PCL interface carries).
  const Eigen::Vector3d v(8.0, 0.2, 0.05);
  for (const bool paper : {false, true}) {
    AutomotiveOdometryOptions o;
    if (paper) o = o.paper(3);
    AutomotiveOdometry matched(o, atNominalGrid(pcl::make_shared<GuessMatcher>()));
    AutomotiveOdometry doppler(o, nullptr);
    for (int k = 0; k < 20; ++k) {
      matched.add(constantCycle(k * 75000, v));
      doppler.add(constantCycle(k * 75000, v));
    }
    EXPECT_EQ(matched.counters().matched, 19u);
    EXPECT_TRUE(matched.steps().back().pose.isApprox(doppler.steps().back().pose, 1e-6))
        << (paper ? "paper" : "default");
    EXPECT_NEAR(matched.steps().back().yaw_rate_bias, 0.0, 1e-6);
  }
}

TEST(AutomotiveOdometry, CycleToMapMatchesTheNewCycleAgainstEarlierCyclesOnly) {
  // The source is the newest cycle alone (50 points), the target the earlier ones in the map.
  AutomotiveOdometryOptions o;
  o.map_cycles = 4;
  AutomotiveOdometry odo(o, atNominalGrid(pcl::make_shared<GuessMatcher>()));
  for (int k = 0; k < 8; ++k) odo.add(constantCycle(k * 75000, Eigen::Vector3d(8.0, 0.0, 0.0)));
  EXPECT_EQ(odo.steps()[1].source_points, 50u);
  EXPECT_EQ(odo.steps()[1].target_points, 50u);
  EXPECT_EQ(odo.steps()[3].target_points, 150u);
  EXPECT_EQ(odo.steps()[7].target_points, 200u) << "at most M = 4 cycles";
  // The paper's mode: submap (N = 3 cycles) to submap.
  AutomotiveOdometry paper(o.paper(3), atNominalGrid(pcl::make_shared<GuessMatcher>()));
  for (int k = 0; k < 8; ++k) paper.add(constantCycle(k * 75000, Eigen::Vector3d(8.0, 0.0, 0.0)));
  EXPECT_EQ(paper.steps()[7].source_points, 150u);
  EXPECT_EQ(paper.steps()[7].target_points, 150u);
  EXPECT_THROW(parseEnum<AutomotiveMatchMode>("scan-to-scan"), std::invalid_argument);
  EXPECT_EQ(parseEnum<AutomotiveMatchMode>("paper"), AutomotiveMatchMode::SubmapToSubmap);
  EXPECT_EQ(parseEnum<AutomotiveMatchMode>(toString(AutomotiveMatchMode::CycleToMap)), AutomotiveMatchMode::CycleToMap);
}

TEST(AutomotiveOdometry, RappWeightsEachCycleAgainstItsOwnMotion) {
  // Two cycles from one radar at the vehicle origin: the first driving straight at 10 m/s, the
  // second turning at 0.5 rad/s. Every point is stationary, its Doppler what its own cycle's motion
  // predicts, but for one moving point in the first cycle (2 m/s off). In the second cycle's
  // submap (N = 2) the first cycle's points must keep weights from the first cycle's motion, in its
  // own frame: ≈ 1, and ≈ 0 for the moving one. Judged against the second cycle's motion at their
  // moved positions (as before), the stationary ones far from the vehicle would fall well below 1.
  const SensorMounting radar{0.0, 0.0, 0.0, true};
  const double dt = 0.075;
  auto cycle = [&](std::int64_t t_us, const Eigen::Vector3d& v, int moving) {
    ProcessedCycle c;
    c.timestamp_us = t_us;
    c.mountings = {radar};
    for (int i = 0; i < 40; ++i) {
      const double a = -1.2 + 0.06 * i, r = 10.0 + 1.5 * i;
      PointRadar p(static_cast<float>(r * std::cos(a)), static_cast<float>(r * std::sin(a)), 0.f);
      p.cov_xx = p.cov_yy = 0.04f;
      p.sensor_id = 0;
      p.doppler = static_cast<float>(predictedDoppler(radar, p.x, p.y, v) + (i == moving ? 2.0 : 0.0));
      c.cloud->push_back(p);
    }
    c.ego.velocity = v;
    c.ego.covariance = Eigen::Matrix3d::Identity() * 1e-6;
    c.ego.valid = true;
    return c;
  };
  const Eigen::Vector3d v1(10.0, 0.0, 0.0), v2(10.0, 0.0, 0.5);
  AutomotiveOdometryOptions o = AutomotiveOdometryOptions{}.paper(2);
  o.doppler_weights = true;
  o.doppler_weight_rounds = 1;
  auto recorder = pcl::make_shared<PowerRecorder>();
  AutomotiveOdometry odo(o, atNominalGrid(recorder));
  odo.add(cycle(0, v1, 7));
  odo.add(cycle(static_cast<std::int64_t>(dt * 1e6), v2, -1));
  ASSERT_EQ(recorder->source_power.size(), 1u);
  const std::vector<float>& w = recorder->source_power[0];
  ASSERT_EQ(w.size(), 80u);
  for (int i = 0; i < 40; ++i) {
    if (i == 7)
      EXPECT_LT(w[i], 1e-6) << "the moving point of the first cycle";
    else
      EXPECT_GT(w[i], 0.999f) << "first cycle, point " << i;
  }
  // The guess is the trapezoid motion, not v2·dt: the newest cycle's weights use it, so they are
  // high but not exactly 1.
  for (int i = 40; i < 80; ++i) EXPECT_GT(w[i], 0.5f) << "second cycle, point " << i - 40;
  // The target is the first cycle weighted against its own ego-velocity.
  ASSERT_EQ(recorder->target_power[0].size(), 40u);
  EXPECT_LT(recorder->target_power[0][7], 1e-6);
  EXPECT_GT(recorder->target_power[0][0], 0.999f);
  // Judged against the second cycle's motion at the moved positions, as before, the far points of
  // the first cycle would be weighted far below 1: the case this test tells apart.
  pcl::PointCloud<PointRadar> moved = *cycle(0, v1, 7).cloud;
  transformWithUncertainty(moved, integrateVelocity(0.5 * (v1 + v2), dt), Eigen::Matrix3d::Zero());
  double worst = 1;
  for (int i = 0; i < 40; ++i) {
    const double e = moved[i].doppler - predictedDoppler(radar, moved[i].x, moved[i].y, v2);
    if (i != 7) worst = std::min(worst, std::exp(-0.5 * e * e / (o.doppler_weight_sigma * o.doppler_weight_sigma)));
  }
  EXPECT_LT(worst, 0.5);
}

TEST(AutomotiveOdometry, DopplerDeadReckoningAndSkippedDuplicateTimestamps) {
  AutomotiveOdometry odo(AutomotiveOdometryOptions{}, nullptr);
  const Eigen::Vector3d v(5.0, 0.0, 0.1);
  odo.add(constantCycle(0, v));
  odo.add(constantCycle(100000, v));
  odo.add(constantCycle(100000, v));  // duplicated timestamp: no second pose
  odo.add(constantCycle(200000, v));
  EXPECT_EQ(odo.counters().skipped, 1u);
  EXPECT_EQ(odo.trajectory().size(), 3u);
  const Pose2 expected = compose(integrateVelocity(v, 0.1), integrateVelocity(v, 0.1));
  EXPECT_TRUE(odo.steps().back().pose.isApprox(expected, 1e-9));
}

TEST(AutomotiveOdometry, InvalidVelocityReusesTheLastOne) {
  AutomotiveOdometry odo(AutomotiveOdometryOptions{}, nullptr);
  odo.add(constantCycle(0, Eigen::Vector3d(5, 0, 0)));
  ProcessedCycle bad = constantCycle(100000, Eigen::Vector3d(50, 0, 0));
  bad.ego.valid = false;
  odo.add(bad);
  EXPECT_EQ(odo.counters().stale_velocity, 1u);
  EXPECT_NEAR(odo.steps().back().pose.x(), 0.5, 1e-9);
}

TEST(AutomotiveOdometry, KeepsNoPointerToTheCallersCloud) {
  // The submap copies each cycle's points: after add() returns, the caller's cloud is its own.
  AutomotiveOdometry odo(AutomotiveOdometryOptions{}, makeMatcher(MatcherOptions::forAutomotive()));
  const Eigen::Vector3d v(10.0, 0.0, 0.0);
  for (int k = 0; k < 4; ++k) {
    ProcessedCycle c = constantCycle(k * 75000, v);
    odo.add(c);
    EXPECT_EQ(c.cloud.use_count(), 1) << "cycle " << k;
  }
}

namespace {

/// A car that rolls its rear wheels at `rpm` and turns at a yaw rate that steps from 0 to 0.2 rad/s
/// at 0.5 s, sampled at 100 Hz from 0 to 3 s (time shifted by `shift_us`).
std::shared_ptr<const VehicleSignals> steppingCar(double rpm, std::int64_t shift_us = 0) {
  auto s = std::make_shared<VehicleSignals>();
  for (std::int64_t t = 0; t <= 3000000; t += 10000) {
    s->yaw_rate.stamps_us.push_back(t + shift_us);
    s->yaw_rate.values.push_back(t < 500000 ? 0.0 : 0.2);
    s->rear_wheel_rpm.stamps_us.push_back(t + shift_us);
    s->rear_wheel_rpm.values.push_back(rpm);
  }
  return s;
}

/// The car's own dead reckoning (wheel-gyro) over cycles every 77 ms: the last step.
OdometryStep deadReckonedCar(const CarSensorOptions& car, const std::shared_ptr<const VehicleSignals>& signals) {
  AutomotiveOdometryOptions o;
  o.car = car;
  o.fuse_doppler = false;
  AutomotiveOdometry odo(o, nullptr);
  odo.setVehicleSignals(signals);
  // The Doppler says something else entirely: the car's sensors make the motion.
  for (int k = 0; k <= 26; ++k) odo.add(constantCycle(k * 77000, Eigen::Vector3d(1.0, 0.0, -0.5)));
  return odo.steps().back();
}

}  // namespace

TEST(AutomotiveOdometry, TheCarsOwnDeadReckoningIntegratesGyroAndWheelsOverEachCycle) {
  CarSensorOptions car;
  car.gyro = car.wheels = true;
  car.wheel_radius = 0.5;
  const double rpm = 120.0;  // 2 rev/s × 2π × 0.5 m = 2π m/s
  const OdometryStep last = deadReckonedCar(car, steppingCar(rpm));
  const double dt = 0.077, speed = 2.0 * kPi;
  // Over the last cycle (1.925 s to 2.002 s) the yaw rate is 0.2 rad/s throughout.
  EXPECT_NEAR(last.motion.z(), 0.2 * dt, 1e-9) << "the gyro's integral over the cycle";
  EXPECT_NEAR(last.motion.head<2>().norm(), speed * dt, 1e-4) << "rpm × 2π r / 60 over the cycle, r the setting";
  // The heading: 0.2 rad/s from 0.5 s to the last cycle's 2.002 s, counter-clockwise positive, and
  // half of it over the 10 ms ramp the samples at 0.49 s and 0.5 s interpolate.
  EXPECT_NEAR(last.pose.z(), 0.2 * (2.002 - 0.5) + 0.5 * 0.2 * 0.01, 1e-9);
  // A CAN clock 0.1 s ahead of the radar's is undone by time_offset.
  car.time_offset = 0.1;
  const OdometryStep shifted = deadReckonedCar(car, steppingCar(rpm, 100000));
  EXPECT_NEAR(shifted.pose.z(), last.pose.z(), 1e-9);
  EXPECT_NEAR((shifted.pose - last.pose).norm(), 0.0, 1e-9);
}

TEST(AutomotiveOdometry, WithCarSensorsButNoSignalsTheRunIsTheDopplerOne) {
  AutomotiveOdometryOptions with_car;
  with_car.car.gyro = with_car.car.wheels = true;
  AutomotiveOdometry a(AutomotiveOdometryOptions{}, nullptr), b(with_car, nullptr);
  for (int k = 0; k < 10; ++k) {
    a.add(constantCycle(k * 77000, Eigen::Vector3d(5.0, 0.1, 0.05)));
    b.add(constantCycle(k * 77000, Eigen::Vector3d(5.0, 0.1, 0.05)));
  }
  EXPECT_EQ(a.steps().back().pose, b.steps().back().pose);
}

// CarFusion: the car's gyro and wheels fused with the Doppler motion and the match. Its bias and
// scale are estimated online: a synthetic gyro bias and wheel scale are recovered from matches; the
// prediction alone is the car's own dead reckoning.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "radar_ndt/odometry/car_fusion.h"

using namespace radar_ndt;

namespace {

/// The motion along an arc of length d turning by theta.
Pose2 arc(double d, double theta) {
  if (std::abs(theta) < 1e-12) return Pose2(d, 0, 0);
  return Pose2(d * std::sin(theta) / theta, d * (1 - std::cos(theta)) / theta, theta);
}

}  // namespace

TEST(CarFusion, TheGyroBiasAndTheWheelScaleAreRecoveredFromTheMatches) {
  CarSensorOptions o;
  o.gyro = o.wheels = true;
  o.gyro_bias_walk = 5e-5;  // a steady bias: recovered to well within its size
  CarFusion f(o, MotionFusionOptions{});
  const double dt = 0.077, v = 10.0, w = 0.1, bias = 0.004, scale = 1.03;
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Matrix3d match_cov = Eigen::Vector3d(0.03 * 0.03, 0.03 * 0.03, 0.001 * 0.001).asDiagonal();
  for (int k = 0; k < 1000; ++k) {
    const Pose2 truth = arc(v * dt, w * dt);
    CarMotion car;
    car.has_yaw = car.has_distance = true;
    car.yaw = (w + bias) * dt;      // the gyro reads the rate plus its bias
    car.distance = v * dt / scale;  // the nominal radius is short: the wheels read short
    const Pose2 doppler = truth + Pose2(0.01 * n(rng), 0.01 * n(rng), 0.01 * n(rng));
    f.predict(car, doppler, Eigen::Matrix3d::Identity() * 1e-4, dt, true);
    f.update(truth + Pose2(0.03 * n(rng), 0.03 * n(rng), 0.001 * n(rng)), match_cov);
  }
  EXPECT_NEAR(f.bias(), bias, 0.0005);
  EXPECT_NEAR(f.wheelScale(), scale, 0.003);
}

TEST(CarFusion, ThePredictionAloneIsTheCarsDeadReckoning) {
  CarSensorOptions o;
  o.gyro = o.wheels = true;
  CarFusion f(o, MotionFusionOptions{});
  CarMotion car;
  car.has_yaw = car.has_distance = true;
  car.yaw = 0.02;
  car.distance = 0.8;
  // No Doppler update: the arc the wheels rolled, turned by the gyro (bias 0, scale 1 at the start).
  const MotionEstimate p = f.predict(car, Pose2(5, 5, 5), Eigen::Matrix3d::Identity(), 0.08, false);
  const Pose2 expected = arc(0.8, 0.02);
  EXPECT_NEAR((p.motion - expected).norm(), 0.0, 1e-12);
  // Without wheels the translation is the Doppler motion's, the yaw still the gyro's.
  car.has_distance = false;
  const MotionEstimate q = f.predict(car, Pose2(0.7, 0.01, 0.5), Eigen::Matrix3d::Identity() * 1e-4, 0.08, true);
  EXPECT_DOUBLE_EQ(q.motion.x(), 0.7);
  EXPECT_DOUBLE_EQ(q.motion.z(), 0.02);
}

TEST(CarFusion, OutOfRangeSettingsAreRefused) {
  CarSensorOptions o;
  o.wheel_radius = 0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = CarSensorOptions{};
  o.gyro_noise = -1;
  EXPECT_THROW(CarFusion(o, MotionFusionOptions{}), std::invalid_argument);
}

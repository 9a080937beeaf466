#include "radar_ndt/sim/imu_model.h"

#include <cmath>
#include <random>

#include "radar_ndt/se2.h"
#include "radar_ndt/sim/radar_sim.h"

namespace radar_ndt {
namespace sim {

void ImuOptions::validate() const {
  checkFields(*this, "ImuOptions");
}

void WheelOptions::validate() const {
  checkFields(*this, "WheelOptions");
}

ImuOptions imuPreset(ImuGrade grade) {
  constexpr double kDeg = kPi / 180.0, kHour = 3600.0;
  ImuOptions o;
  switch (grade) {
    case ImuGrade::None: break;
    case ImuGrade::Mems:
      // A consumer MEMS gyro (docs/simulator.md: the Xsens MTi-1's noise density and in-run bias
      // stability; the turn-on bias and scale error of consumer parts).
      o.noise_density = 0.007 * kDeg;
      o.bias_instability = 10.0 * kDeg / kHour;
      o.turn_on_bias = 0.2 * kDeg;
      o.scale_error = 0.005;
      break;
    case ImuGrade::Navigation:
      // A navigation-grade fibre-optic gyro as fitted in Applanix POS LV systems (docs/simulator.md:
      // LN-200 class: angle random walk 0.07°/√h, bias 1°/h, scale factor 100 ppm).
      o.noise_density = 0.07 * kDeg / 60.0;
      o.bias_instability = 0.1 * kDeg / kHour;
      o.turn_on_bias = 1.0 * kDeg / kHour;
      o.scale_error = 1e-4;
      break;
  }
  return o;
}

std::vector<BoreasImuRow> simulateImu(const SimTrajectory& ego, double t_begin, double t_end, double t0,
                                      std::int64_t stamp0_us, const ImuOptions& options, std::uint64_t seed) {
  options.validate();
  std::mt19937_64 rng(seed ^ 0x1f3a5c7e9b2d4f60ULL);  // its own stream: the scans' draws are untouched
  std::normal_distribution<double> normal(0.0, 1.0);
  const double dt = 1.0 / options.rate;
  const double scale = 1.0 + options.scale_error * normal(rng);
  double bias = options.turn_on_bias * normal(rng);
  const double walk = options.bias_instability / std::sqrt(options.bias_time) * std::sqrt(dt);
  const double white = options.noise_density * std::sqrt(options.rate);  // per sample, 1σ
  std::vector<BoreasImuRow> rows;
  if (!(t_end > t_begin)) return rows;
  rows.reserve(static_cast<std::size_t>((t_end - t_begin) / dt) + 2);
  for (std::int64_t i = 0;; ++i) {
    const double t = t_begin + static_cast<double>(i) * dt;
    if (t > t_end) break;
    const Eigen::Vector3d v = ego.velocity(t);  // body frame: forward, left, yaw rate
    const Eigen::Vector3d v_next = ego.velocity(t + dt);
    BoreasImuRow r;
    r.stamp_us = stamp0_us + static_cast<std::int64_t>(std::llround((t - t0) * 1e6));
    // Applanix axes: x right, y forward, z up.
    r.angular_velocity = {white * normal(rng), white * normal(rng), scale * v.z() + bias + white * normal(rng)};
    const double forward = (v_next.x() - v.x()) / dt, left = v.x() * v.z();
    r.acceleration = {-left, forward, 0.0};
    rows.push_back(r);
    bias += walk * normal(rng);
  }
  return rows;
}

void simulateCanBus(const SimTrajectory& ego, double t_begin, double t_end, double t0, std::int64_t stamp0_us,
                    const ImuOptions& imu, const WheelOptions& wheels, std::uint64_t seed,
                    std::vector<CanImuMessage>& imu_out, std::vector<CanWheelMessage>& wheels_out) {
  wheels.validate();
  imu_out.clear();
  wheels_out.clear();
  // The gyro as in the Boreas layout, turned into the IMU's axes (x forward, y left, z up).
  for (const BoreasImuRow& r : simulateImu(ego, t_begin, t_end, t0, stamp0_us, imu, seed)) {
    CanImuMessage m;
    m.utime = r.stamp_us;
    m.rotation_rate = {r.angular_velocity.y(), -r.angular_velocity.x(), r.angular_velocity.z()};
    m.linear_accel = {r.acceleration.y(), -r.acceleration.x(), 9.81};
    const double h = ego.at(t0 + 1e-6 * static_cast<double>(r.stamp_us - stamp0_us)).z();
    m.q = {std::cos(0.5 * h), 0.0, 0.0, std::sin(0.5 * h)};
    imu_out.push_back(m);
  }
  std::mt19937_64 rng(seed ^ 0x5a17c0debeef1234ULL);  // its own stream
  std::normal_distribution<double> normal(0.0, 1.0);
  const double radius = wheels.radius * (1.0 + wheels.radius_error * normal(rng));
  const double dt = 1.0 / wheels.rate, to_rpm = 60.0 / (2.0 * kPi * radius);
  for (std::int64_t i = 0;; ++i) {
    const double t = t_begin + static_cast<double>(i) * dt;
    if (t > t_end) break;
    const Eigen::Vector3d v = ego.velocity(t);  // at the rear axle, the ego frame's origin
    CanWheelMessage m;
    m.utime = stamp0_us + static_cast<std::int64_t>(std::llround((t - t0) * 1e6));
    const double half = 0.5 * wheels.track * v.z();
    m.rl = (v.x() - half) * to_rpm + wheels.noise * normal(rng);
    m.rr = (v.x() + half) * to_rpm + wheels.noise * normal(rng);
    m.fl = m.rl;
    m.fr = m.rr;
    wheels_out.push_back(m);
  }
}

}  // namespace sim
}  // namespace radar_ndt

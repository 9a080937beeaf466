#pragma once
// A simulated gyro beside the simulated scans (beyond the paper, which names IMU fusion as its
// future work). No real gyro beside real scanning-radar scans exists here, so radar_sim writes one
// with the error terms a datasheet gives: a turn-on bias (constant over a sequence), an in-run
// bias that wanders (bias instability, as a random walk), white rate noise (angle random walk)
// and a scale-factor error. Two presets: a consumer MEMS unit and a navigation-grade one like
// Boreas's Applanix; docs/simulator.md gives their figures and sources.

#include <cstdint>
#include <vector>

#include "radar_ndt/fields.h"
#include "radar_ndt/io/boreas_imu.h"
#include "radar_ndt/io/nuscenes_can_bus.h"

namespace radar_ndt {
namespace sim {

class SimTrajectory;

enum class ImuGrade { None, Mems, Navigation };

/// The gyro's error terms, rad and s. The accelerometer is written without errors (gravity
/// removed, as the released Boreas files); nothing here reads it.
struct ImuOptions {
  double rate = 200.0;            ///< Hz (the Applanix's)
  double noise_density = 0.0;     ///< rad/s/√Hz: white rate noise (angle random walk)
  double turn_on_bias = 0.0;      ///< rad/s: 1σ of the bias drawn once a sequence
  double bias_instability = 0.0;  ///< rad/s: the in-run bias's wander over bias_time ...
  double bias_time = 100.0;       ///< s: ... as a random walk of bias_instability / √bias_time per √s
  double scale_error = 0.0;       ///< 1σ of the scale-factor error drawn once a sequence
  void validate() const;
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void ImuOptions::fields(Visit&& visit) {
  using S = ImuOptions;
  visit(&S::rate, Field("imu_rate", "Hz the gyro is sampled at").positive());
  visit(&S::noise_density, Field("imu_noise_density", "rad/s/√Hz white rate noise (angle random walk)").atLeast(0));
  visit(&S::turn_on_bias, Field("imu_turn_on_bias", "rad/s, 1σ of the bias drawn once a sequence").atLeast(0));
  visit(&S::bias_instability,
        Field("imu_bias_instability", "rad/s the in-run bias wanders over imu_bias_time").atLeast(0));
  visit(&S::bias_time, Field("imu_bias_time", "s over which the bias wanders by imu_bias_instability").positive());
  visit(&S::scale_error, Field("imu_scale_error", "1σ of the scale-factor error drawn once a sequence").atLeast(0));
}

/// A car's wheel-speed sensors (the rear wheels, rpm on the CAN bus).
struct WheelOptions {
  double rate = 100.0;          ///< Hz (nuScenes' zoe_veh_info)
  double radius = 0.305;        ///< m: the nominal rolling radius
  double radius_error = 0.005;  ///< 1σ of the true radius's relative error, drawn once a sequence
  double noise = 0.5;           ///< rpm, white noise on each message
  double track = 1.5;           ///< m between the rear wheels
  void validate() const;
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void WheelOptions::fields(Visit&& visit) {
  using S = WheelOptions;
  visit(&S::rate, Field("wheel_rate", "Hz the wheel speeds are sent at").positive());
  visit(&S::radius, Field("wheel_radius", "m, the wheels' nominal rolling radius").positive());
  visit(&S::radius_error,
        Field("wheel_radius_error", "1σ of the true radius's relative error, drawn once a sequence").atLeast(0));
  visit(&S::noise, Field("wheel_noise", "rpm, white noise on each wheel-speed message").atLeast(0));
  visit(&S::track, Field("wheel_track", "m between the rear wheels").positive());
}

/// The preset's figures (docs/simulator.md); None: a perfect gyro.
ImuOptions imuPreset(ImuGrade grade);

/// Gyro (and error-free accelerometer) rows over [t_begin, t_end] of `ego` at options.rate, in
/// the Boreas Applanix frame (x right, y forward, z up); row time t is stamped
/// stamp0_us + (t − t0) s. Deterministic for `seed`.
std::vector<BoreasImuRow> simulateImu(const SimTrajectory& ego, double t_begin, double t_end, double t0,
                                      std::int64_t stamp0_us, const ImuOptions& options, std::uint64_t seed);

/// The car's CAN bus as nuScenes' devkit lays it out: ms_imu (the gyro of `imu` about z up, at its
/// rate; gravity in the accelerations; the heading as the attitude's yaw) and zoe_veh_info (each
/// rear wheel's speed at the true radius, the front ones equal to them), over [t_begin, t_end],
/// stamped stamp0_us + (t − t0) s. Deterministic for `seed`.
void simulateCanBus(const SimTrajectory& ego, double t_begin, double t_end, double t0, std::int64_t stamp0_us,
                    const ImuOptions& imu, const WheelOptions& wheels, std::uint64_t seed,
                    std::vector<CanImuMessage>& imu_out, std::vector<CanWheelMessage>& wheels_out);

}  // namespace sim

template <>
struct EnumNames<sim::ImuGrade> {
  static constexpr const char* what = "IMU grade";
  static constexpr EnumName<sim::ImuGrade> names[] = {
      {sim::ImuGrade::None, "none", "no IMU file"},
      {sim::ImuGrade::Mems, "mems", "a consumer MEMS gyro"},
      {sim::ImuGrade::Navigation, "navigation", "a navigation-grade gyro (as Boreas's Applanix)"}};
};

}  // namespace radar_ndt

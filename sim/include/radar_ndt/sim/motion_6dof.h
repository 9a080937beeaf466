#pragma once
// Any 6-DoF trajectory as a smooth motion, the 6-axis IMU that rides it, and a 4D radar sequence
// along it in a world built around the path: what drives the 4D simulator with real motion (a
// hand-held rig's TUM file, a car's Boreas poses) so that the doppler-imu baseline and part 2's
// odometry are measured against a known truth.
//
// The motion is a uniform cumulative cubic B-spline (Kim et al. 1995; as in continuous-time
// visual-inertial odometry) over the trajectory resampled every `knot_spacing` s: twice
// differentiable, so the IMU's angular velocity and specific force are the motion's own
// derivatives and the truth written beside the scans is the spline itself, not the file.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <pcl/point_cloud.h>

#include "radar_ndt/fields.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/odometry/doppler_imu.h"
#include "radar_ndt/point_types.h"
#include "radar_ndt/sim/radar_4d.h"

namespace radar_ndt {
namespace sim {

class Motion6Dof {
 public:
  /// The spline through `trajectory` (stamps needed, at least 4 poses, increasing), its poses
  /// resampled every `knot_spacing` s (gaps bridged as the file's interpolation bridges them).
  /// std::invalid_argument otherwise.
  explicit Motion6Dof(const Trajectory& trajectory, double knot_spacing = 0.25);
  double start() const { return t0_ + dt_; }  ///< the spline's valid span
  double end() const { return t0_ + dt_ * static_cast<double>(knots_.size() - 2); }
  /// The body's pose (body to world) at t, within [start, end].
  Eigen::Isometry3d pose(double t) const;
  Eigen::Vector3d velocity(double t) const;         ///< world frame, m/s
  Eigen::Vector3d acceleration(double t) const;     ///< world frame, m/s²
  Eigen::Vector3d angularVelocity(double t) const;  ///< body frame, rad/s
  /// The path's length over [start, end] (m), sampled every 0.1 s.
  double length() const;

 private:
  double t0_ = 0, dt_ = 0.25;
  std::vector<Eigen::Isometry3d> knots_;
};

/// A 6-axis IMU's error terms (gyro rad/s, accelerometer m/s²), per axis.
struct Imu6Options {
  double rate = 200.0;               ///< Hz
  double gyro_noise_density = 0.0;   ///< rad/s/√Hz (angle random walk)
  double gyro_turn_on_bias = 0.0;    ///< rad/s, 1σ, drawn once a sequence
  double gyro_bias_walk = 0.0;       ///< rad/s/√s: the in-run bias's random walk
  double accel_noise_density = 0.0;  ///< m/s²/√Hz (velocity random walk)
  double accel_turn_on_bias = 0.0;   ///< m/s², 1σ, drawn once a sequence
  double accel_bias_walk = 0.0;      ///< m/s²/√s
  double gravity = 9.81;             ///< m/s²
  void validate() const;
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void Imu6Options::fields(Visit&& visit) {
  using S = Imu6Options;
  visit(&S::rate, Field("rate", "IMU messages a second").unit("Hz").positive());
  visit(&S::gyro_noise_density, Field("gyro_noise_density", "gyro white noise").unit("rad/s/sqrt(Hz)").atLeast(0));
  visit(&S::gyro_turn_on_bias,
        Field("gyro_turn_on_bias", "1 sigma of the gyro bias drawn once").unit("rad/s").atLeast(0));
  visit(&S::gyro_bias_walk, Field("gyro_bias_walk", "the gyro bias's random walk").unit("rad/s/sqrt(s)").atLeast(0));
  visit(&S::accel_noise_density,
        Field("accel_noise_density", "accelerometer white noise").unit("m/s^2/sqrt(Hz)").atLeast(0));
  visit(&S::accel_turn_on_bias,
        Field("accel_turn_on_bias", "1 sigma of the accelerometer bias drawn once").unit("m/s^2").atLeast(0));
  visit(&S::accel_bias_walk,
        Field("accel_bias_walk", "the accelerometer bias's random walk").unit("m/s^2/sqrt(s)").atLeast(0));
  visit(&S::gravity, Field("gravity", "the local gravity").unit("m/s^2").positive());
}

/// "none" (exact readings), "mems" (the rio rig's Analog Devices ADIS16448: its datasheet's angle
/// and velocity random walk and in-run bias stability), "navigation" (a fibre-optic navigation
/// grade as Boreas's Applanix carries); std::invalid_argument otherwise. docs/simulator.md cites
/// the figures.
Imu6Options imu6Preset(const std::string& grade);

/// The IMU's messages along `motion` over its span: the gyro reads the body's angular velocity,
/// the accelerometer the specific force Rᵀ(a + g ẑ) (+g along the body's up at rest), each with
/// `o`'s errors from `seed`.
std::vector<ImuSample> simulateImu6(const Motion6Dof& motion, const Imu6Options& o, std::uint64_t seed);

/// A world around a path: for a hand-held rig (`car` false) corridors of walls 2.5-7 m either side
/// with doors, pillars, a floor 1.2 m below and a ceiling 1.6 m above the rig; for a car buildings
/// 8-15 m either side with gaps, poles, parked cars and the ground 1.5 m below the radar, following
/// the path's height. Nothing is placed within 1 m of any part of the path. The world goes on
/// straight past the path's end along its last heading (a car 100 m, a hand-held rig 15 m).
World3D worldAlongPath(const Motion6Dof& motion, bool car, std::uint64_t seed);

/// A 4D radar sequence along `motion`: scans at `rate` Hz from the radar at `mounting` on the body
/// (radar to body; identity: at the body's origin with its axes) in `world`, in the radar's frame
/// with its own velocity's Doppler, the IMU beside them (at the body's origin, its axes), and the
/// body's truth at each scan.
struct Radar4DSequence {
  std::vector<double> stamps;  ///< s, one a scan
  std::vector<pcl::PointCloud<PointRadar4D>> scans;
  std::vector<ImuSample> imu;
  Trajectory truth;  ///< the body's pose at each scan
};
Radar4DSequence simulateRadar4DSequence(const Motion6Dof& motion, const World3D& world, const Radar4DModel& model,
                                        double rate, const Imu6Options& imu, std::uint64_t seed,
                                        const Eigen::Isometry3d& mounting = Eigen::Isometry3d::Identity());

}  // namespace sim
}  // namespace radar_ndt

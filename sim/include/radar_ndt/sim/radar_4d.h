#pragma once
// A 4D radar (x, y, z, Doppler, power) in a 3D world, for the 3D matcher's tests and benchmarks:
// a world of boxes (buildings, walls, parked cars, stair steps), vertical poles and flat or sloped
// patches (ground, ramps), and a radar model per preset (field of view in azimuth and elevation,
// range limits, range/azimuth/elevation/Doppler noise, detections per scan, false alarms and
// multipath ghosts below the ground). Each detection carries the covariance its sensor
// description's spherical accuracy gives (radar_ndt/frontend/point_covariance.h).
// docs/simulator.md: the presets' figures and where they come from.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <pcl/point_cloud.h>

#include "radar_ndt/frontend/point_covariance.h"
#include "radar_ndt/point_types.h"
#include "radar_ndt/se3.h"

namespace radar_ndt {
namespace sim {

struct Box3 {
  Eigen::Vector3d min, max;
  float rcs = 10.f;  ///< dBsm
};
struct Pole3 {
  Eigen::Vector2d xy;
  double radius = 0.15, height = 4.0;
  float rcs = 5.f;
};
/// A flat parallelogram origin + s·u + t·v, s, t in [0, 1] (the ground, a ramp).
struct Patch3 {
  Eigen::Vector3d origin, u, v;
  float rcs = -5.f;
};

struct World3D {
  std::vector<Box3> boxes;
  std::vector<Pole3> poles;
  std::vector<Patch3> patches;
  /// The nearest hit of the ray from `o` along unit `d` within `max_range`: its distance and the
  /// hit's RCS; false when nothing is hit.
  bool cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double max_range, double* range, float* rcs) const;
};

/// A street: buildings on both sides with gaps, poles, parked cars, the ground and a ramp up to a
/// raised stretch; for cars. Around the x axis from x = −50 to `length` m.
World3D streetWorld(double length, std::uint64_t seed);
/// A building's corridors: floor, ceiling, walls with doors and pillars, a staircase; for hand-held
/// rigs. Within a 60 m x 40 m floor around the origin.
World3D corridorWorld(std::uint64_t seed);

/// A 4D radar's model (sensor frame: x forward, y left, z up).
struct Radar4DModel {
  std::string name;
  double azimuth_fov_deg = 120, elevation_fov_deg = 30;  ///< full widths, centred on x
  double min_range = 0.5, max_range = 100;               ///< m
  SphericalAccuracy accuracy;                            ///< 1σ noise, and each point's covariance
  double doppler_sigma = 0.05;                           ///< m/s
  int rays = 1000;                                       ///< directions tried a scan
  double detection_probability = 0.9;                    ///< of a ray that hits
  double false_alarms = 5;                               ///< mean false detections a scan
  double ghost_fraction = 0.02;                          ///< detections mirrored below the ground
  /// Power as an SNR (dB): snr_offset + RCS − 20 log10(range) + N(0, snr_sigma²).
  double snr_offset = 30.0, snr_sigma = 2.0;
  /// Detections whose SNR falls below it are not reported (a driver's CFAR threshold, dB); 0: every
  /// hit is, its SNR floored at 1.
  double min_snr = 0.0;
};
/// The presets: "ti_iwr6843_rio", "ars548", "oculii_eagle"; std::invalid_argument otherwise.
Radar4DModel radar4DPreset(const std::string& name);
std::vector<std::string> radar4DPresetNames();
/// The sensor description preset (config/sensors/) that reads a preset's recordings as its driver
/// writes them: ti_iwr6843_rio, snail_radar_ars548, ntu4dradlm_eagle; std::invalid_argument otherwise.
std::string radar4DSensorPreset(const std::string& preset);

/// One scan from the sensor pose `pose` (sensor to world) moving with `velocity` (m/s, world
/// frame): detections in the sensor frame with power 1, RCS, radial Doppler (positive receding)
/// and covariance; `stream` picks the scan's random numbers.
pcl::PointCloud<PointRadar4D> simulateScan4D(const World3D& world, const Pose3& pose, const Eigen::Vector3d& velocity,
                                             const Radar4DModel& model, std::uint64_t seed, std::uint64_t stream);

/// A scan-to-map registration problem: the map of `map_scans` scans (world frame) before the
/// source scan (its sensor frame), the source's true pose in the map's frame and a guess off by
/// `translation_error` m and `rotation_error` rad in random directions.
struct ScanToMapPair {
  pcl::PointCloud<PointRadar4D> map, source;
  Pose3 truth, guess;
};
struct ScanToMapOptions {
  std::string preset = "oculii_eagle";
  int map_scans = 5;
  double speed = 10.0;       ///< m/s along the path
  double scan_period = 0.1;  ///< s
  double translation_error = 1.0;
  double rotation_error = 5.0 * 3.14159265358979323846 / 180.0;
  /// The preset's range, angle and Doppler noise (and so its points' covariances) scaled by this.
  double noise_scale = 1.0;
};
/// Pair `index` of a sequence from `seed`: a car along the street for the car presets, a
/// hand-held walk with roll and pitch wobble through the corridors for "ti_iwr6843_rio".
ScanToMapPair scanToMapPair(const ScanToMapOptions& options, std::uint64_t seed, int index);

}  // namespace sim
}  // namespace radar_ndt

#pragma once
// Vehicle ego-velocity from the Doppler of several radars in one cycle (Kellner et al. 2014,
// "Instantaneous ego-motion estimation using multiple Doppler radars"): a stationary target seen
// by a sensor mounted at (mx, my) in the vehicle frame, in direction φ (vehicle axes), has
//   v_r = −[cos φ, sin φ, mx sin φ − my cos φ] · [vx, vy, ω]ᵀ
// (the sensor moves with v + ω × m). RANSAC on that linear model rejects moving objects and ghosts,
// then least squares on the inliers gives the estimate and its 3x3 covariance.

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <pcl/point_cloud.h>

#include "radar_ndt/point_types.h"

namespace radar_ndt {

/// Where a radar sits on the vehicle (vehicle frame: x forward, y left), in 2D.
struct SensorMounting {
  double x = 0, y = 0, yaw = 0;
  bool valid = false;  ///< false for sensor ids no sweep of this cycle came from
};

/// Ego-velocity (vx, vy, yaw rate) in the vehicle frame, m/s and rad/s.
struct EgoVelocity {
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  std::size_t points = 0;   ///< detections offered
  std::size_t inliers = 0;  ///< detections consistent with the estimate (stationary)
  double residual_rms = 0;  ///< of the inliers (m/s)
  bool valid = false;       ///< false: too few or degenerate detections; velocity then meaningless
};

/// Doppler a stationary point at (px, py) (vehicle frame) shows to the sensor `m` when the vehicle
/// moves with `v` = (vx, vy, ω).
double predictedDoppler(const SensorMounting& m, double px, double py, const Eigen::Vector3d& v);

class EgoVelocityEstimator {
 public:
  struct Options {
    double inlier_threshold = 0.25;  ///< |v_r − predicted| (m/s) for a RANSAC inlier
    int max_iterations = 150;
    std::size_t min_inliers = 6;
    double min_inlier_ratio = 0.2;  ///< below this the cycle is called invalid (mostly moving scene)
    std::uint32_t seed = 42;        ///< fixed: the same input gives the same answer
  };

  EgoVelocityEstimator() = default;
  explicit EgoVelocityEstimator(const Options& o) : options_(o) {}
  void setOptions(const Options& o) { options_ = o; }
  const Options& options() const { return options_; }

  /// `cloud` in the vehicle frame; `mountings` indexed by PointRadar::sensor_id. Points of
  /// sensors without a valid mounting, or non-finite, are ignored. `inlier` (optional) gets one
  /// flag per point of `cloud`.
  EgoVelocity estimate(const pcl::PointCloud<PointRadar>& cloud, const std::vector<SensorMounting>& mountings,
                       std::vector<bool>* inlier = nullptr) const;

 private:
  Options options_;
};

}  // namespace radar_ndt

#pragma once
// Vehicle ego-velocity from the Doppler of several radars in one cycle (Kellner et al. 2014,
// "Instantaneous ego-motion estimation using multiple Doppler radars"): a stationary target seen
// by a sensor mounted at (mx, my) in the vehicle frame, in direction φ (vehicle axes), has
//   v_r = −[cos φ, sin φ, mx sin φ − my cos φ] · [vx, vy, ω]ᵀ
// (the sensor moves with v + ω × m). RANSAC on that linear model rejects moving objects and ghosts,
// then least squares on the inliers gives the estimate and its 3x3 covariance. Beyond the paper,
// the least squares also observes vy = 0 with σ EgoVelocityOptions::lateral_sigma: the vehicle frame's origin
// (nuScenes: the rear axle) barely slides sideways, and without that prior the poorly observed vy
// trades against ω.
//
// One radar (or several at one place) sees only its own velocity, 2 of the 3 unknowns: ω × m is
// then indistinguishable from a sideways v. There the estimator falls back to the single-radar
// method of Kellner et al. 2013 ("Instantaneous ego-motion estimation using Doppler radar"): the
// vehicle does not slide sideways at the vehicle frame's origin (vy = 0; nuScenes' ego frame is the
// rear axle's midpoint, where that holds for a car off the limit), leaving
//   v_r = −[cos φ, mx sin φ − my cos φ] · [vx, ω]ᵀ,
// solvable when the radar sits off the rear axle (mx ≠ 0). On the rear axle's line (mx = 0: a radar
// at the base frame's origin, as Snail-Radar's ARS548) it sees only its forward speed vx − ω my;
// the fit then gives that alone and leaves ω unknown, for the matcher to find.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <pcl/point_cloud.h>

#include "radar_ndt/fields.h"
#include "radar_ndt/io/radar_cycle.h"
#include "radar_ndt/point_types.h"

namespace radar_ndt {

/// Which kinematic model the Doppler fit uses.
enum class EgoVelocityModel {
  Auto,          ///< Full when the radars with detections sit at least 0.2 m apart, else Nonholonomic
  Full,          ///< (vx, vy, ω) free: needs radars at two or more places (Kellner 2014)
  Nonholonomic,  ///< vy = 0 at the vehicle frame's origin, (vx, ω) fitted (Kellner 2013)
};

template <>
struct EnumNames<EgoVelocityModel> {
  static constexpr const char* what = "ego-velocity model";
  static constexpr EnumName<EgoVelocityModel> names[] = {
      {EgoVelocityModel::Auto, "auto", "full when radars sit at two places or more, else nonholonomic"},
      {EgoVelocityModel::Full, "full", "vx, vy and the yaw rate"},
      {EgoVelocityModel::Nonholonomic, "nonholonomic", "vy = 0: one radar suffices"}};
};

/// Ego-velocity (vx, vy, yaw rate) in the vehicle frame, m/s and rad/s.
struct EgoVelocity {
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  std::size_t points = 0;   ///< detections offered
  std::size_t inliers = 0;  ///< detections consistent with the estimate (stationary)
  double residual_rms = 0;  ///< of the inliers (m/s)
  bool valid = false;       ///< false: too few or degenerate detections; velocity then meaningless
  /// The fit used vy = 0 (EgoVelocityModel::Nonholonomic, chosen or forced); vy's variance is then
  /// EgoVelocityOptions::lateral_sigma², uncorrelated.
  bool nonholonomic = false;
  /// Nonholonomic with the radars on the rear axle's line (|mx| < 0.2 m, at one place): the fit gave
  /// the forward speed alone; ω is 0 with variance (1 rad/s)², i.e. unknown.
  bool forward_only = false;
};

/// Doppler a stationary point at (px, py) (vehicle frame) shows to the sensor `m` when the vehicle
/// moves with `v` = (vx, vy, ω).
double predictedDoppler(const SensorMounting& m, double px, double py, const Eigen::Vector3d& v);

struct EgoVelocityOptions {
  double inlier_threshold = 0.25;  ///< |v_r − predicted| (m/s) for a RANSAC inlier
  int max_iterations = 150;
  std::size_t min_inliers = 6;
  double min_inlier_ratio = 0.2;  ///< below this the cycle is called invalid (mostly moving scene)
  std::uint32_t seed = 42;        ///< fixed: the same input gives the same answer
  EgoVelocityModel model = EgoVelocityModel::Auto;
  /// m/s, 1σ: how far vy ≈ 0 at the vehicle frame's origin is trusted. The full model's least
  /// squares observes vy = 0 with this σ (a prior: 300 detections still outweigh it when they
  /// see a slide); the nonholonomic model reports it as vy's σ. A car's side slip at the rear axle
  /// is about 0.3° at 2 m/s² lateral acceleration, 0.05 m/s at 10 m/s. 0: no prior (Kellner
  /// 2014 as published; the nonholonomic model then reports vy's σ as 1 m/s).
  double lateral_sigma = 0.05;
  /// Throws std::invalid_argument naming the setting out of range.
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void EgoVelocityOptions::fields(Visit&& visit) {
  using S = EgoVelocityOptions;
  visit(&S::inlier_threshold,
        Field("inlier_threshold", "ego-velocity RANSAC inlier and moving-detection threshold on |Doppler - predicted|")
            .unit("m/s")
            .positive()
            .cli("doppler-threshold"));
  visit(&S::max_iterations, Field("max_iterations", "RANSAC iterations").atLeast(1));
  visit(&S::min_inliers, Field("min_inliers", "inliers a valid estimate needs").atLeast(2));
  visit(&S::min_inlier_ratio,
        Field("min_inlier_ratio", "below this inlier share the cycle's estimate is invalid").atLeast(0).atMost(1));
  visit(&S::seed, Field("seed", "RANSAC's seed: the same input gives the same answer"));
  visit(&S::model, Field("model", "the kinematic model of the fit").cli("ego-model"));
  visit(&S::lateral_sigma, Field("lateral_sigma",
                                 "σ of the prior vy = 0 at the vehicle origin (nuScenes: the rear axle); 0: none, the "
                                 "plain 3-DoF fit")
                               .unit("m/s")
                               .atLeast(0)
                               .cli("lateral-sigma"));
}

class EgoVelocityEstimator {
 public:
  EgoVelocityEstimator() = default;
  /// Validates `o` (std::invalid_argument).
  explicit EgoVelocityEstimator(const EgoVelocityOptions& o) : options_(o) { options_.validate(); }
  void setOptions(const EgoVelocityOptions& o) {
    o.validate();
    options_ = o;
  }
  const EgoVelocityOptions& options() const { return options_; }

  /// `cloud` in the vehicle frame; `mountings` indexed by PointRadar::sensor_id. Points of
  /// sensors without a valid mounting, or non-finite, are ignored. `inlier` (optional) gets one
  /// flag per point of `cloud`.
  EgoVelocity estimate(const pcl::PointCloud<PointRadar>& cloud, const std::vector<SensorMounting>& mountings,
                       std::vector<bool>* inlier = nullptr) const;

 private:
  EgoVelocityOptions options_;
};

}  // namespace radar_ndt

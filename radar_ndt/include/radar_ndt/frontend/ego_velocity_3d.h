#pragma once
// A 4D radar's own 3D velocity from the Doppler of one scan. A stationary target in direction u
// (unit vector from the radar, radar axes) shows the radial velocity
//   v_r = −u · v
// (positive receding, PointRadar's and PointRadar4D's convention), v the radar's velocity. Three
// detections in independent directions fix v: no mounting, no motion model, no yaw-rate coupling as
// in the planar estimator (ego_velocity.h), since a 4D radar measures elevation. RANSAC on that
// model rejects moving objects and ghosts (Kellner et al. 2013's scheme, in 3D as the
// radar-inertial odometry of Doer and Trommer 2020 uses it), then least squares on the inliers
// gives v and its covariance, scaled by the inliers' residual variance. bodyVelocity() moves the
// result to the vehicle's or rig's origin with the radar's mounting and the angular velocity.
// A scan where the static world is not the largest consistent set (a lorry filling the view, false
// alarms facing an empty field) fools RANSAC; given a prediction of v (an IMU carried from the last
// scan, as EKF-RIO gates the radar's velocity by its Mahalanobis distance), only hypotheses within
// its gate count, the prediction itself among them, and an estimate outside it is refused.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <pcl/point_cloud.h>

#include "radar_ndt/fields.h"

namespace radar_ndt {

/// The radar's velocity (m/s, radar axes) from one scan.
struct EgoVelocity3D {
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  std::size_t points = 0;   ///< finite detections offered (beyond min_range)
  std::size_t inliers = 0;  ///< consistent with the estimate: the static world
  double residual_rms = 0;  ///< of the inliers (m/s)
  bool valid = false;       ///< false: `why` says so; velocity then meaningless
  std::string why;          ///< empty when valid
};

struct EgoVelocity3DOptions {
  double inlier_threshold = 0.2;  ///< |v_r − predicted| (m/s) for a RANSAC inlier
  int max_iterations = 200;
  std::size_t min_inliers = 6;
  double min_inlier_ratio = 0.2;  ///< below this the scan is called invalid (mostly moving scene)
  /// m/s, 1σ: the smallest Doppler noise the covariance may claim (a radar's velocity resolution);
  /// above it the inliers' own residual variance scales the covariance.
  double doppler_sigma = 0.03;
  double min_range = 0.3;   ///< m: nearer detections (leakage, the rig itself) are left out
  std::uint32_t seed = 42;  ///< fixed: the same input gives the same answer
  /// Throws std::invalid_argument naming the setting out of range.
  void validate() const;
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void EgoVelocity3DOptions::fields(Visit&& visit) {
  using S = EgoVelocity3DOptions;
  visit(&S::inlier_threshold,
        Field("inlier_threshold", "RANSAC inlier and moving-detection threshold on |Doppler - predicted|")
            .unit("m/s")
            .positive());
  visit(&S::max_iterations, Field("max_iterations", "RANSAC iterations").atLeast(1));
  visit(&S::min_inliers, Field("min_inliers", "inliers a valid estimate needs").atLeast(3));
  visit(&S::min_inlier_ratio,
        Field("min_inlier_ratio", "below this inlier share the scan's estimate is invalid").atLeast(0).atMost(1));
  visit(&S::doppler_sigma,
        Field("doppler_sigma", "smallest Doppler noise the covariance claims").unit("m/s").positive());
  visit(&S::min_range, Field("min_range", "nearer detections are left out").unit("m").atLeast(0));
  visit(&S::seed, Field("seed", "RANSAC's seed: the same input gives the same answer"));
}

/// A prediction of the radar's velocity (radar axes) from another sensor, with its covariance.
struct EgoVelocityPrior {
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  /// Squared Mahalanobis distance beyond which a velocity is not the radar's: χ²(3) at 99.9 %.
  double gate = 16.27;
};

class EgoVelocity3DEstimator {
 public:
  EgoVelocity3DEstimator() = default;
  /// Validates `o` (std::invalid_argument).
  explicit EgoVelocity3DEstimator(const EgoVelocity3DOptions& o) : options_(o) { options_.validate(); }
  const EgoVelocity3DOptions& options() const { return options_; }

  /// `positions` and `doppler` one per detection, in the radar's frame (origin at the radar).
  /// Non-finite detections and those nearer than min_range are left out. `inlier` (optional) gets
  /// one flag per detection: true for the static world the estimate explains. With a `prior`,
  /// RANSAC's hypotheses beyond its gate are passed over and the prior's velocity is one of them;
  /// an estimate beyond the gate (its covariance and the prior's) is invalid, and `inlier` then
  /// flags the detections the prior's velocity explains within its own uncertainty.
  EgoVelocity3D estimate(const std::vector<Eigen::Vector3d>& positions, const std::vector<double>& doppler,
                         std::vector<bool>* inlier = nullptr, const EgoVelocityPrior* prior = nullptr) const;

  /// Any PCL cloud with x, y, z and a `doppler` field (PointRadar, PointRadar4D), radar frame.
  template <typename PointT>
  EgoVelocity3D estimate(const pcl::PointCloud<PointT>& cloud, std::vector<bool>* inlier = nullptr,
                         const EgoVelocityPrior* prior = nullptr) const {
    std::vector<Eigen::Vector3d> positions;
    std::vector<double> doppler;
    positions.reserve(cloud.size());
    doppler.reserve(cloud.size());
    for (const PointT& p : cloud) {
      positions.emplace_back(p.x, p.y, p.z);
      doppler.push_back(p.doppler);
    }
    return estimate(positions, doppler, inlier, prior);
  }

 private:
  EgoVelocity3DOptions options_;
};

/// The Doppler a static point at `position` (radar frame) shows to a radar moving with `velocity`.
inline double predictedDoppler3D(const Eigen::Vector3d& position, const Eigen::Vector3d& velocity) {
  return -position.normalized().dot(velocity);
}

/// The velocity of the body's origin, body axes, from the radar's (radar axes): the radar moves
/// with v_b + ω × t, so v_b = R v_r − ω × t (`radar_to_body` = [R | t], ω the body's angular
/// velocity, rad/s, body axes: a gyro's reading after its own mounting).
inline Eigen::Vector3d bodyVelocity(const Eigen::Isometry3d& radar_to_body, const Eigen::Vector3d& radar_velocity,
                                    const Eigen::Vector3d& angular_velocity) {
  return radar_to_body.linear() * radar_velocity - angular_velocity.cross(radar_to_body.translation());
}

/// The covariance of bodyVelocity() (ω taken as exact): R Σ Rᵀ.
inline Eigen::Matrix3d bodyVelocityCovariance(const Eigen::Isometry3d& radar_to_body, const Eigen::Matrix3d& cov) {
  return radar_to_body.linear() * cov * radar_to_body.linear().transpose();
}

/// Several radars' body velocities at one time (each with its covariance) as one, weighted by their
/// information: C = (Σ Cᵢ⁻¹)⁻¹, v = C Σ Cᵢ⁻¹ vᵢ. One is returned as it is; none is not allowed.
inline std::pair<Eigen::Vector3d, Eigen::Matrix3d> fuseBodyVelocities(
    const std::vector<std::pair<Eigen::Vector3d, Eigen::Matrix3d>>& velocities) {
  if (velocities.size() == 1) return velocities.front();
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
  for (const auto& [v, C] : velocities) {
    const Eigen::Matrix3d inv = C.inverse();
    information += inv;
    weighted += inv * v;
  }
  const Eigen::Matrix3d cov = information.inverse();
  return {cov * weighted, cov};
}

}  // namespace radar_ndt

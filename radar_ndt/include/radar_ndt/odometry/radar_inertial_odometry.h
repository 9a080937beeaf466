#pragma once
// 6-DoF odometry for a 4D radar, with or without an IMU: the paper's method carried to 3D and to
// the fusion its conclusion asks for. Each scan:
//  1. front-end: the radar's 3D Doppler velocity (ego_velocity_3d.h); its inliers are the static
//     world, the rest (moving objects, ghosts) are left out of matching; the body velocity follows
//     from the mounting and the angular velocity. With an IMU, the velocity it predicts from the
//     last scan's (imu_velocity.h) gates it: a Doppler consensus beyond it is refused and the
//     prediction moves the prior instead;
//  2. prior: with an IMU, the inertial filter (inertial_filter.h) carried to the scan's time, the
//     gyro turning and the Doppler velocity moving it, then gravity holding roll and pitch; radar
//     only, the last scan's rotation rate and the Doppler velocity;
//  3. match: the scan (body frame) against the local map of recent keyframes (local_map_3d.h) by a
//     3D matcher of the registry (matcher_registry_3d.h: pw-ndt-3d, pcl-ndt-3d, pcl-gicp), from
//     the prior;
//  4. fusion: with an IMU, the match updates the filter with its covariance (WeightedNDT3D's,
//     scaled, or a fixed one for matchers without one) and is refused beyond the gate; radar only,
//     the match is the pose. No accepted match: the prior stands and the step says why.
// Each part usable alone; doppler_imu.h is the baseline without matching.

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>

#include "radar_ndt/fields.h"
#include "radar_ndt/frontend/ego_velocity_3d.h"
#include "radar_ndt/io/imu_sample.h"
#include "radar_ndt/odometry/inertial_filter.h"
#include "radar_ndt/odometry/local_map_3d.h"
#include "radar_ndt/odometry/matcher_registry_3d.h"
#include "radar_ndt/point_types.h"

namespace radar_ndt {

struct RadarInertialOptions {
  std::string method = "pw-ndt-3d";  ///< a 3D matcher of the registry
  bool use_imu = true;               ///< false: radar only (IMU messages are ignored)
  double min_range = 0.3;            ///< m: nearer detections are left out
  double max_range = 300.0;          ///< m: farther ones too
  std::size_t min_points = 6;        ///< static detections a scan needs to be matched
  /// The match's covariance (WeightedNDT3D's own, the floors for matchers without one) is scaled
  /// by a factor that starts here and follows the innovations at `match_scale_rate` a match.
  double match_covariance_scale = 100.0;
  double match_scale_rate = 0.05;
  /// 1σ floors of a match (and the whole covariance of matchers that give none).
  double match_sigma_translation = 0.05;  ///< m
  double match_sigma_rotation_deg = 0.5;  ///< deg
  /// Fused runs: whether the match's roll and pitch count. A 4D radar's elevation is coarse, so
  /// by default gravity alone holds them and the match gives yaw and position.
  bool match_roll_pitch = false;
  /// Standing still: the Doppler velocity's squared Mahalanobis distance from zero below
  /// still_velocity_chi2 (χ²(3) at 95 %) and, radar only, the turn rate below still_rate.
  double still_velocity_chi2 = 7.81;
  double still_rate = 0.02;      ///< rad/s
  double imu_time_offset = 0.0;  ///< s added to the IMU's stamps to bring them to the radar's clock
  /// Each detection with a time_offset (a driver's per-point time, the description's `time:`)
  /// moved to the step's time under the step's velocity and turn rate (deskewBody).
  bool deskew = true;
  /// With an IMU: each scan's Doppler velocity checked against the IMU's prediction from the last
  /// scan's (RANSAC's hypotheses within its gate, χ²(3) at 99.9 %; from zero at a still start).
  /// The prediction's 1σ: the last accepted velocity's, velocity_prior_floor (what the Doppler and
  /// the two clocks get wrong at any time) and velocity_prior_sigma a second since that velocity.
  bool velocity_prior = true;
  double velocity_prior_floor = 0.1;  ///< m/s
  double velocity_prior_sigma = 0.3;  ///< m/s²
  /// Radar only, the same gate on a constant-velocity prediction: the last velocity held in the
  /// world as the body turns at its last turn rate, its 1σ growing by
  /// velocity_prior_radar_only_sigma a second (what the rig's own acceleration can change). Off by
  /// default: the turn rate comes from the matches, and where they fail (a hand-held TI rig) the
  /// prediction and the radar's lever arm carry their error into the gate (docs/odometry_6dof.md).
  bool velocity_prior_radar_only = false;
  double velocity_prior_radar_only_sigma = 3.0;  ///< m/s²
  LocalMap3DOptions map;
  EgoVelocity3DOptions ego_velocity;
  InertialFilterOptions filter;
  Matcher3DOptions matchers;
  /// Throws std::invalid_argument naming the setting out of range or the unknown method.
  void validate() const;
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void RadarInertialOptions::fields(Visit&& visit) {
  using S = RadarInertialOptions;
  visit(&S::min_range, Field("min_range", "nearer detections are left out").unit("m").atLeast(0));
  visit(&S::max_range, Field("max_range", "farther detections are left out").unit("m").positive());
  visit(&S::min_points, Field("min_points", "static detections a scan needs to be matched").atLeast(3));
  visit(&S::match_covariance_scale,
        Field("match_covariance_scale", "the match covariance's starting factor").positive());
  visit(&S::match_scale_rate,
        Field("match_scale_rate", "how fast that factor follows the innovations (log step a match)").atLeast(0));
  visit(&S::match_sigma_translation,
        Field("match_sigma_translation", "1 sigma floor of a match's translation").unit("m").positive());
  visit(&S::match_sigma_rotation_deg,
        Field("match_sigma_rotation_deg", "1 sigma floor of a match's rotation").unit("deg").positive());
  visit(&S::match_roll_pitch, Field("match_roll_pitch", "fused runs: the match's roll and pitch count too"));
  visit(&S::still_velocity_chi2,
        Field("still_velocity_chi2", "standing still: the Doppler velocity's chi-square from zero below this")
            .atLeast(0));
  visit(&S::still_rate,
        Field("still_rate", "standing still, radar only: the turn rate below this").unit("rad/s").atLeast(0));
  visit(&S::imu_time_offset,
        Field("imu_time_offset", "added to the IMU's stamps to bring them to the radar's clock").unit("s"));
  visit(&S::deskew, Field("deskew", "detections with a per-point time moved to the scan's time (de-skew)"));
  visit(&S::velocity_prior,
        Field("velocity_prior", "with an IMU, each scan's Doppler velocity gated by the IMU's prediction"));
  visit(&S::velocity_prior_floor,
        Field("velocity_prior_floor", "the IMU's predicted velocity's smallest 1 sigma").unit("m/s").atLeast(0));
  visit(
      &S::velocity_prior_sigma,
      Field("velocity_prior_sigma", "how fast the IMU's predicted velocity grows uncertain").unit("m/s^2").positive());
  visit(&S::velocity_prior_radar_only,
        Field("velocity_prior_radar_only", "radar only, each scan's Doppler velocity gated by the last one's"));
  visit(
      &S::velocity_prior_radar_only_sigma,
      Field("velocity_prior_radar_only_sigma", "radar only: how fast the last velocity grows uncertain as a prediction")
          .unit("m/s^2")
          .positive());
  visit(&S::map, Field("map", "the local map"));
  visit(&S::ego_velocity, Field("ego_velocity", "the 3D Doppler ego-velocity"));
  visit(&S::filter, Field("filter", "the inertial filter"));
  visit(&S::matchers, Field("matchers", "the 3D matchers' settings"));
}

/// Moves each detection of `body` (body frame, measured at the step's time plus its time_offset)
/// into the body at the step's time, the body turning at `omega` and moving at `velocity` (body
/// axes) over the offsets, a sweep's tens of milliseconds: p <- Exp(omega t) p + v t +
/// (omega x v) t^2 / 2, its covariance turned with it; time_offset then 0. Points with no offset
/// are left as they are.
void deskewBody(pcl::PointCloud<PointRadar4D>& body, const Eigen::Vector3d& velocity, const Eigen::Vector3d& omega);

/// What one scan gave.
struct OdometryStep3D {
  double stamp = 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< body to the odometry frame
  Matrix6d covariance = Matrix6d::Zero();                  ///< (δp, δθ), the filter's; radar only the match's
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      ///< body axes, m/s (held when not valid)
  bool velocity_valid = false;
  bool matched = false;   ///< a match was accepted
  bool fallback = false;  ///< no match accepted (not said of the first scan): the prior stands
  bool still = false;     ///< standing still: not moved, not matched (after a still scan)
  bool skipped = false;   ///< no pose: before the IMU's still start was read (`why` says so)
  std::string why;        ///< why not, when fallback
  int iterations = 0;
  double match_ms = 0;
  std::size_t points = 0, static_points = 0;
};

/// One radar's scan in a step of several (radars measuring at the same time).
struct RadarScan4D {
  const pcl::PointCloud<PointRadar4D>* scan = nullptr;  ///< radar frame
  Eigen::Isometry3d radar_to_body = Eigen::Isometry3d::Identity();
  std::uint16_t radar = 0;  ///< which radar (its keyframes in the local map are its own)
};

class RadarInertialOdometry {
 public:
  /// `radar_to_body`: the radar's mounting. Validates `o` (std::invalid_argument).
  explicit RadarInertialOdometry(const RadarInertialOptions& o = {},
                                 const Eigen::Isometry3d& radar_to_body = Eigen::Isometry3d::Identity());
  ~RadarInertialOdometry();
  RadarInertialOdometry(const RadarInertialOdometry&) = delete;
  RadarInertialOdometry& operator=(const RadarInertialOdometry&) = delete;

  /// One IMU message (body axes, the IMU's clock). Messages not finite or not later than the last
  /// are dropped and counted in problems().
  void addImu(const ImuSample& sample);
  /// One scan (radar frame, PointRadar4D with Doppler and covariances) at `stamp` (s). With an IMU,
  /// scans before the IMU spans its still start (InertialFilterOptions::initial_seconds) are
  /// skipped (their step has no pose, `skipped` set), as is a scan not later than the last.
  OdometryStep3D addScan(double stamp, const pcl::PointCloud<PointRadar4D>& scan);
  /// The scans of several radars at `stamp` (one or more, each with its mounting), as one step: each
  /// radar's Doppler ego-velocity turned into the body's, the valid ones fused by their
  /// information; their static detections matched together. One scan is addScan's step.
  OdometryStep3D addScans(double stamp, const std::vector<RadarScan4D>& scans);

  const LocalMap3D& map() const { return map_; }
  const InertialFilter& filter() const { return filter_; }
  /// Each problem met, said once with its figures (IMU messages dropped, gravity off the body's z, ...).
  std::vector<std::string> problems() const;

 private:
  struct Motion;
  Motion priorMotion(double stamp, const Eigen::Vector3d& velocity, const Eigen::Matrix3d& velocity_covariance);
  void match(const pcl::PointCloud<PointRadar4D>::Ptr& source, OdometryStep3D& step);
  /// The body velocity (with its covariance) predicted at `stamp` from the last scan's: the IMU's,
  /// or radar only the last velocity turned by the last turn rate; false with the setting off
  /// (velocity_prior, velocity_prior_radar_only), or before the first scan (with an IMU, after a
  /// start that was not still).
  bool velocityPrediction(double stamp, Eigen::Vector3d& velocity, Eigen::Matrix3d& covariance) const;
  /// Each radar's detections in range, its Doppler ego-velocity (the valid ones into `egos`; with
  /// a `predicted` body velocity, gated by it at the angular velocity `omega`) and its static
  /// detections moved into the body frame, all radars' together (counted in `step`).
  pcl::PointCloud<PointRadar4D>::Ptr frontEnd(const std::vector<RadarScan4D>& scans, OdometryStep3D& step,
                                              std::vector<std::pair<const RadarScan4D*, EgoVelocity3D>>& egos,
                                              const std::pair<Eigen::Vector3d, Eigen::Matrix3d>* predicted,
                                              const Eigen::Vector3d& omega);
  /// The step's body velocity and its covariance: the valid radars' Doppler velocities fused (then
  /// the last accepted), else the IMU's prediction, else the last step's held (1 m/s, 1σ).
  std::pair<Eigen::Vector3d, Eigen::Matrix3d> stepVelocity(
      double stamp, const std::vector<std::pair<const RadarScan4D*, EgoVelocity3D>>& egos,
      const std::pair<Eigen::Vector3d, Eigen::Matrix3d>* predicted, const Eigen::Vector3d& omega);
  /// Whether the scan at `stamp` gets a pose: later than the last, the filter started (from the
  /// IMU's still start) when fused. Says why not in `step`.
  bool ready(double stamp, OdometryStep3D& step);
  /// Keeps what the next scan needs of this one; a keyframe joins the local map.
  void remember(const OdometryStep3D& step, const Eigen::Matrix3d& velocity_covariance,
                const pcl::PointCloud<PointRadar4D>& source, std::uint16_t radar);

  RadarInertialOptions options_;
  Eigen::Isometry3d radar_to_body_;
  EgoVelocity3DEstimator ego_;
  InertialFilter filter_;
  LocalMap3D map_;
  std::shared_ptr<Registration3D> matcher_;
  const Matcher3DEntry* entry_ = nullptr;
  std::size_t target_version_ = 0, map_version_ = 0;
  std::vector<ImuSample> imu_;  ///< messages not yet used, time-ordered
  ImuSample last_imu_;          ///< the IMU state's time and the reading it holds
  std::size_t dropped_imu_ = 0;
  std::vector<std::string> problems_;
  bool started_ = false;
  double last_stamp_ = 0;
  Eigen::Isometry3d pose_ = Eigen::Isometry3d::Identity();   ///< radar only
  Eigen::Vector3d rotation_rate_ = Eigen::Vector3d::Zero();  ///< radar only: body axes, rad/s
  Eigen::Vector3d last_velocity_ = Eigen::Vector3d::Zero();
  double match_scale_ = 1;
  bool last_still_ = false;
  Eigen::Matrix3d last_velocity_covariance_ = Eigen::Matrix3d::Identity();
  bool predicting_ = false;    ///< a velocity to predict from: a still start or a first scan
  double accepted_stamp_ = 0;  ///< the last scan whose Doppler velocity was taken
  Eigen::Matrix3d accepted_covariance_ = Eigen::Matrix3d::Identity();
};

}  // namespace radar_ndt

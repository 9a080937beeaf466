#pragma once
// The motion gates that call a converged match a failure (paper, Sec. IV-A: a match implying an
// acceleration above the motion prior of 8 m/s² is not trusted). The two pipelines gate
// differently, and each gate is kept here as its pipeline has always used it, side by side:
//  - automotive: the displacement against the last one rescaled to this interval (a·dt²), plus a
//    chi-square test against the Doppler ego-motion; no yaw bound;
//  - scanning: the velocity against the last accepted match's, over the time between the two
//    intervals' middles (a·elapsed·dt), with a yaw-rate bound.

#include <Eigen/Core>

#include "radar_ndt/fields.h"
#include "radar_ndt/odometry/motion_model.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

struct AutomotiveMotionGateOptions {
  /// false: a converged match is always accepted (no motion-prior or Doppler check), as plain
  /// submap matching (Holder et al.) does.
  bool enabled = true;
  double max_acceleration = 8.0;  ///< motion prior (m/s²)
  /// Matching noise allowed on top of the motion prior and in the chi-square test: 1σ of a
  /// match's translation (m) and rotation (rad).
  double match_sigma_xy = 0.05;
  double match_sigma_yaw = 0.005;
  double chi2_threshold = 16.27;  ///< 3 degrees of freedom, 99.9 %
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void AutomotiveMotionGateOptions::fields(Visit&& visit) {
  using S = AutomotiveMotionGateOptions;
  visit(&S::enabled, Field("enabled", "check each converged match against the motion prior and the Doppler motion")
                         .offSwitch("no-gate",
                                    "accept every converged match: no motion-prior (nor, nuscenes, "
                                    "Doppler chi-square) check (ablation)"));
  visit(&S::max_acceleration,
        Field("max_acceleration", "the motion prior's acceleration").unit("m/s²").atLeast(0).orInfinite());
  visit(&S::match_sigma_xy, Field("match_sigma_xy", "1σ of a match's translation").unit("m").atLeast(0));
  visit(&S::match_sigma_yaw, Field("match_sigma_yaw", "1σ of a match's rotation").unit("rad").atLeast(0));
  visit(&S::chi2_threshold, Field("chi2_threshold", "the Doppler chi-square bound (3 DoF)").positive());
}

class AutomotiveMotionGate {
 public:
  explicit AutomotiveMotionGate(const AutomotiveMotionGateOptions& options = {}) : options_(options) {}

  /// Whether `motion` (over `dt` s) is plausible: its displacement within a·dt² + 3·√2·σ_xy of
  /// `prior`'s last one rescaled to dt (when the prior has one), and the chi-square of
  /// motion − guess with covariance guess_cov + diag(σ_xy², σ_xy², σ_yaw²) at most the threshold.
  /// `*chi2` gets that chi-square (infinity when the motion prior refused it; 0 when disabled).
  bool accept(const Pose2& motion, const Pose2& guess, const Eigen::Matrix3d& guess_cov, double dt,
              const ConstantVelocityModel& prior, double* chi2) const;

 private:
  AutomotiveMotionGateOptions options_;
};

struct ScanningMotionGateOptions {
  /// false: a converged match is always accepted (no motion-prior check), as for the automotive
  /// gate (`--no-gate` in both pipelines).
  bool enabled = true;
  double max_acceleration = 8.0;  ///< motion prior (m/s²)
  /// Yaw-rate change allowed per second (rad/s²): a sanity bound far above what a car does.
  double max_yaw_acceleration = 4.0;
  /// 1σ matching noise (m, rad) added to the motion-prior bounds, as in the automotive gate.
  double match_sigma_xy = 0.05;
  double match_sigma_yaw = 0.005;
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void ScanningMotionGateOptions::fields(Visit&& visit) {
  using S = ScanningMotionGateOptions;
  visit(&S::enabled, Field("enabled", "check each converged match against the motion prior")
                         .offSwitch("no-gate",
                                    "accept every converged match: no motion-prior (nor, nuscenes, "
                                    "Doppler chi-square) check (ablation)"));
  visit(&S::max_acceleration,
        Field("max_acceleration", "the motion prior's acceleration").unit("m/s²").atLeast(0).orInfinite());
  visit(
      &S::max_yaw_acceleration,
      Field("max_yaw_acceleration", "the yaw rate's change allowed per second").unit("rad/s²").atLeast(0).orInfinite());
  visit(&S::match_sigma_xy, Field("match_sigma_xy", "1σ of a match's translation").unit("m").atLeast(0));
  visit(&S::match_sigma_yaw, Field("match_sigma_yaw", "1σ of a match's rotation").unit("rad").atLeast(0));
}

class ScanningMotionGate {
 public:
  explicit ScanningMotionGate(const ScanningMotionGateOptions& options = {}) : options_(options) {}

  /// Whether `motion` over `dt` s, an interval whose middle is at `mid_time` (s), is plausible
  /// against the last trusted match: its velocity differs by at most a·Δt (Δt the time between the
  /// two middles, at least dt), i.e. its displacement by a·Δt·dt plus the noise of two matches.
  /// Δt grows across fallbacks, so one bad estimate cannot lock the gate. True before any trust().
  bool accept(const Pose2& motion, double dt, double mid_time) const;
  /// Makes `motion` over `dt`, centred at `mid_time`, the match later ones are judged against.
  void trust(const Pose2& motion, double dt, double mid_time);

 private:
  ScanningMotionGateOptions options_;
  Eigen::Vector3d trusted_velocity_ = Eigen::Vector3d::Zero();
  double trusted_mid_time_ = 0;
  bool have_trusted_ = false;
};

}  // namespace radar_ndt

#include "radar_ndt/odometry/motion_gate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/LU>

namespace radar_ndt {

void AutomotiveMotionGateOptions::validate() const {
  checkFields(*this, "AutomotiveMotionGateOptions");
}

bool AutomotiveMotionGate::accept(const Pose2& motion, const Pose2& guess, const Eigen::Matrix3d& guess_cov, double dt,
                                  const ConstantVelocityModel& prior, double* chi2) const {
  const double sxy2 = options_.match_sigma_xy * options_.match_sigma_xy;
  const double syaw2 = options_.match_sigma_yaw * options_.match_sigma_yaw;
  *chi2 = 0;
  if (!options_.enabled) return true;
  // Motion prior: the velocity change since the last accepted motion is at most a·dt, i.e. the
  // displacement differs by at most a·dt² from the last one rescaled to this dt, plus matching
  // noise (3σ of the difference of two matches).
  if (prior.hasVelocity()) {
    const Eigen::Vector2d expected = prior.rescaledTranslation(dt);
    const double bound = options_.max_acceleration * dt * dt + 3.0 * std::sqrt(2.0 * sxy2);
    if ((motion.head<2>() - expected).norm() > bound) {
      *chi2 = std::numeric_limits<double>::infinity();
      return false;
    }
  }
  // Agreement with the Doppler ego-velocity: r = match − Doppler integral, S = Σ_doppler + Σ_match.
  Eigen::Vector3d r = motion - guess;
  r.z() = normalizeAngle(r.z());
  Eigen::Matrix3d S = guess_cov;
  S(0, 0) += sxy2;
  S(1, 1) += sxy2;
  S(2, 2) += syaw2;
  *chi2 = r.dot(S.inverse() * r);
  return *chi2 <= options_.chi2_threshold;
}

void ScanningMotionGateOptions::validate() const {
  checkFields(*this, "ScanningMotionGateOptions");
}

bool ScanningMotionGate::accept(const Pose2& motion, double dt, double mid_time) const {
  if (!options_.enabled) return true;
  if (!have_trusted_) return true;  // no accepted match yet: nothing to check against
  // The velocity of this interval (at its middle) differs from the last accepted match's (at its
  // middle) by at most a·Δt; over dt that is a displacement difference of a·Δt·dt, plus the noise
  // of two matches.
  const double elapsed = std::max(dt, mid_time - trusted_mid_time_);
  const Pose2 predicted = integrateVelocity(trusted_velocity_, dt);
  const double bound_xy = options_.max_acceleration * elapsed * dt + 3.0 * std::sqrt(2.0) * options_.match_sigma_xy;
  const double bound_yaw =
      options_.max_yaw_acceleration * elapsed * dt + 3.0 * std::sqrt(2.0) * options_.match_sigma_yaw;
  return (motion.head<2>() - predicted.head<2>()).norm() <= bound_xy &&
         std::abs(normalizeAngle(motion.z() - predicted.z())) <= bound_yaw;
}

void ScanningMotionGate::trust(const Pose2& motion, double dt, double mid_time) {
  trusted_velocity_ = velocityOf(motion, dt);
  trusted_mid_time_ = mid_time;
  have_trusted_ = true;
}

}  // namespace radar_ndt

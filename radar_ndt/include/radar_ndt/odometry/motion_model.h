#pragma once
// The motion prior both odometries predict from: the last accepted motion and its interval.
// The two pipelines extrapolate it differently (they have since the paper's first version);
// both formulas live here, side by side, until the pipelines agree on one.

#include <Eigen/Core>

#include "radar_ndt/se2.h"

namespace radar_ndt {

class ConstantVelocityModel {
 public:
  /// The motion accepted for the last step and the interval it took (s).
  void update(const Pose2& motion, double dt) {
    last_motion_ = motion;
    last_dt_ = dt;
  }
  /// Whether a motion with a positive interval has been seen (the first step gives none).
  bool hasVelocity() const { return last_dt_ > 0; }
  /// The constant body velocity (vx, vy, ω) of the last motion, log(motion) / dt on SE(2); zero
  /// before there is one.
  Eigen::Vector3d velocity() const {
    return last_dt_ > 0 ? velocityOf(last_motion_, last_dt_) : Eigen::Vector3d::Zero();
  }
  /// The motion over `dt` at that velocity, exp(v·dt) (the scanning guess, and bridged steps).
  Pose2 predict(double dt) const { return integrateVelocity(velocity(), dt); }
  /// The last displacement rescaled linearly to `dt` (the automotive motion gate's expectation);
  /// only meaningful when hasVelocity().
  Eigen::Vector2d rescaledTranslation(double dt) const { return last_motion_.head<2>() * (dt / last_dt_); }

 private:
  Pose2 last_motion_ = Pose2::Zero();
  double last_dt_ = 0;
};

}  // namespace radar_ndt

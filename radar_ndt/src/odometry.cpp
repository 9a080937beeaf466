#include "radar_ndt/odometry.h"

#include <chrono>
#include <cmath>

#include <Eigen/LU>

namespace radar_ndt {

const char* toString(StepStatus s) {
  switch (s) {
    case StepStatus::First: return "first";
    case StepStatus::Matched: return "matched";
    case StepStatus::Retried: return "retried";
    case StepStatus::Fallback: return "fallback";
    case StepStatus::DeadReckoned: return "dead-reckoned";
    case StepStatus::Skipped: return "skipped";
  }
  return "?";
}

namespace {
double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

Odometry::Odometry(const OdometryOptions& options, RadarRegistration::Ptr matcher)
    : options_(options), matcher_(std::move(matcher)), submap_(options.submap_size) {}

Trajectory Odometry::trajectory() const {
  Trajectory t;
  for (const auto& s : steps_) {
    if (s.status == StepStatus::Skipped) continue;
    t.stamps.push_back(1e-6 * static_cast<double>(s.timestamp_us));
    t.poses.push_back(toIsometry3(s.pose));
  }
  return t;
}

bool Odometry::accept(const Pose2& motion, const Pose2& guess, const Eigen::Matrix3d& guess_cov, double dt, double* chi2) const {
  const double sxy2 = options_.match_sigma_xy * options_.match_sigma_xy;
  const double syaw2 = options_.match_sigma_yaw * options_.match_sigma_yaw;
  *chi2 = 0;
  if (!options_.gate) return true;
  // Motion prior: the velocity change since the last accepted motion is at most a·dt, i.e. the
  // displacement differs by at most a·dt² from the last one rescaled to this dt, plus matching
  // noise (3σ of the difference of two matches).
  if (last_dt_ > 0) {
    const Eigen::Vector2d expected = last_accepted_motion_.head<2>() * (dt / last_dt_);
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

void Odometry::weightByDoppler(pcl::PointCloud<PointRadar>& cloud, const std::vector<SensorMounting>& mountings, const Pose2& motion,
                               double dt) const {
  // Velocity that the motion implies (first order), then each point's Doppler agreement.
  const Eigen::Vector3d v = motion / dt;
  const double inv = 1.0 / (options_.doppler_weight_sigma * options_.doppler_weight_sigma);
  for (auto& p : cloud) {
    double w = 0;
    if (p.sensor_id < mountings.size() && mountings[p.sensor_id].valid) {
      const double e = p.doppler - predictedDoppler(mountings[p.sensor_id], p.x, p.y, v);
      w = std::exp(-0.5 * e * e * inv);
    }
    p.power = static_cast<float>(w);
  }
}

const OdometryStep& Odometry::add(const ProcessedCycle& cycle) {
  OdometryStep step;
  step.timestamp_us = cycle.timestamp_us;
  ++counters_.cycles;
  const OdometryStep* prev = nullptr;
  for (auto it = steps_.rbegin(); it != steps_.rend(); ++it)
    if (it->status != StepStatus::Skipped) {
      prev = &*it;
      break;
    }
  if (prev && cycle.timestamp_us <= prev->timestamp_us) {
    step.status = StepStatus::Skipped;
    step.pose = prev->pose;
    ++counters_.skipped;
    steps_.push_back(step);
    return steps_.back();
  }

  // The cycle's ego-velocity, or the last one with a grown covariance.
  EgoVelocity ego = cycle.ego;
  step.velocity_valid = ego.valid;
  if (!ego.valid) {
    ++counters_.stale_velocity;
    if (have_velocity_) {
      ego = last_velocity_;
    } else {
      ego.velocity.setZero();
      ego.covariance.setIdentity();
    }
    const double s2 = options_.stale_velocity_sigma * options_.stale_velocity_sigma;
    ego.covariance += Eigen::Vector3d(s2, s2, s2 * 0.1).asDiagonal().toDenseMatrix();
  } else {
    last_velocity_ = ego;
    have_velocity_ = true;
  }

  const double dt = prev ? 1e-6 * static_cast<double>(cycle.timestamp_us - prev->timestamp_us) : 0.0;
  auto t0 = std::chrono::steady_clock::now();
  submap_.add(*cycle.cloud, ego.velocity, ego.covariance, dt);
  pcl::PointCloud<PointRadar>::Ptr source = submap_.cloud();
  step.submap_ms = msSince(t0);

  if (!prev) {
    step.status = StepStatus::First;
    target_ = source;
    steps_.push_back(step);
    return steps_.back();
  }

  const Pose2 guess = submap_.lastMotion();
  const Eigen::Matrix3d guess_cov = submap_.lastMotionCovariance();
  step.doppler_motion = guess;
  step.source_points = source->size();
  step.target_points = target_ ? target_->size() : 0;
  Pose2 motion = guess;
  bool ok = false;
  if (!matcher_ || step.source_points < options_.min_points || step.target_points < options_.min_points) {
    step.status = StepStatus::DeadReckoned;
    ++counters_.dead_reckoned;
    ok = true;
  } else {
    t0 = std::chrono::steady_clock::now();
    pcl::PointCloud<PointRadar> aligned;
    for (int attempt = 0; attempt <= options_.max_retries && !ok; ++attempt) {
      const double g = options_.grid + options_.grid_step * attempt;
      if (attempt == 0)
        matcher_->setInputTarget(target_);  // builds the target model at the nominal grid
      else
        setMatcherGrid(*matcher_, g);  // rebuilds it, enlarged
      Pose2 estimate = guess;
      const int rounds = options_.doppler_weights ? std::max(1, options_.doppler_weight_rounds) : 1;
      bool converged = false;
      for (int round = 0; round < rounds; ++round) {
        // Rapp: weights from the initial guess, then from each round's estimate (a failed attempt's
        // estimate must not carry over into the next attempt).
        if (options_.doppler_weights) weightByDoppler(*source, cycle.mountings, estimate, dt);
        matcher_->setInputSource(source);
        matcher_->align(aligned, toMatrix4<float>(estimate));
        converged = matcher_->hasConverged();
        if (!converged) break;
        estimate = toPose2(matcher_->getFinalTransformation());
      }
      step.attempts = attempt + 1;
      step.grid = g;
      if (converged && estimate.allFinite() && accept(estimate, guess, guess_cov, dt, &step.chi2)) {
        motion = estimate;
        ok = true;
        step.status = attempt == 0 ? StepStatus::Matched : StepStatus::Retried;
      }
    }
    if (ok) {
      ++(step.status == StepStatus::Matched ? counters_.matched : counters_.retried);
    } else {
      step.status = StepStatus::Fallback;
      ++counters_.fallbacks;
      motion = guess;
    }
    step.match_ms = msSince(t0);
    if (step.grid != options_.grid) setMatcherGrid(*matcher_, options_.grid);
  }
  step.motion = motion;
  step.pose = compose(prev->pose, motion);
  last_accepted_motion_ = motion;
  last_dt_ = dt;
  target_ = source;
  steps_.push_back(step);
  return steps_.back();
}

}  // namespace radar_ndt

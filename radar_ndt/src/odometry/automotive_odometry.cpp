#include "radar_ndt/odometry/automotive_odometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "detail/run_timing.h"

namespace radar_ndt {

using detail::msSince;

void AutomotiveOdometryOptions::validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("AutomotiveOdometryOptions: " + what); };
  if (submap_size < 1) fail("submap_size must be >= 1");
  if (!(grid > 0) || !std::isfinite(grid)) fail("grid must be > 0, got " + std::to_string(grid));
  if (!(grid_step >= 0) || !std::isfinite(grid_step)) fail("grid_step must be >= 0");
  if (max_retries < 0) fail("max_retries must be >= 0");
  if (!(stale_velocity_sigma >= 0)) fail("stale_velocity_sigma must be >= 0");
  if (!(doppler_weight_sigma > 0)) fail("doppler_weight_sigma must be > 0");
  gate.validate();
}

AutomotiveOdometry::AutomotiveOdometry(const AutomotiveOdometryOptions& options, MatcherAdapter matcher)
    : options_(options), matcher_(std::move(matcher)), gate_(options.gate), submap_(options.submap_size) {
  options_.validate();
}

EgoVelocity AutomotiveOdometry::egoVelocityOf(const ProcessedCycle& cycle) {
  EgoVelocity ego = cycle.ego;
  if (!ego.valid) {
    ++log_.counters().stale_velocity;
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
  return ego;
}

const OdometryStep& AutomotiveOdometry::add(const ProcessedCycle& cycle) {
  if (!cycle.cloud) throw std::invalid_argument("AutomotiveOdometry::add: the cycle has no cloud");
  OdometryStep step = log_.begin(cycle.timestamp_us);
  const OdometryStep* prev = log_.previous();
  if (prev && cycle.timestamp_us <= prev->timestamp_us) return log_.addSkipped(step, *prev);

  step.velocity_valid = cycle.ego.valid;
  const EgoVelocity ego = egoVelocityOf(cycle);
  const double dt = prev ? 1e-6 * static_cast<double>(cycle.timestamp_us - prev->timestamp_us) : 0.0;
  const auto t0 = detail::Clock::now();
  submap_.add(*cycle.cloud, ego.velocity, ego.covariance, dt);
  pcl::PointCloud<PointRadar>::Ptr source = submap_.cloud();
  step.submap_ms = msSince(t0);

  if (!prev) {
    step.status = StepStatus::First;
    target_ = source;
    return log_.add(step);
  }

  const Pose2 guess = submap_.lastMotion();
  step.doppler_motion = guess;
  step.source_points = source->size();
  step.target_points = target_ ? target_->size() : 0;
  Pose2 motion = guess;
  if (!matcher_ || step.source_points < options_.min_points || step.target_points < options_.min_points) {
    step.status = StepStatus::DeadReckoned;
    ++log_.counters().dead_reckoned;
  } else {
    motion = matchWithRetries(cycle, source, guess, submap_.lastMotionCovariance(), dt, step);
  }
  step.motion = motion;
  step.pose = compose(prev->pose, motion);
  motion_model_.update(motion, dt);
  target_ = source;
  return log_.add(step);
}

Pose2 AutomotiveOdometry::matchWithRetries(const ProcessedCycle& cycle, const pcl::PointCloud<PointRadar>::Ptr& source,
                                           const Pose2& guess, const Eigen::Matrix3d& guess_cov, double dt, OdometryStep& step) {
  const auto t0 = detail::Clock::now();
  RadarRegistration& matcher = matcher_.registration();
  Pose2 motion = guess;
  bool ok = false;
  for (int attempt = 0; attempt <= options_.max_retries && !ok; ++attempt) {
    const double g = options_.grid + options_.grid_step * attempt;
    if (attempt == 0)
      matcher.setInputTarget(target_);  // builds the target model at the nominal grid
    else
      matcher_.setGrid(g);  // rebuilds it, enlarged
    Pose2 estimate = guess;
    const int rounds = options_.doppler_weights ? std::max(1, options_.doppler_weight_rounds) : 1;
    bool converged = false;
    for (int round = 0; round < rounds; ++round) {
      // Rapp: weights from the initial guess, then from each round's estimate (a failed attempt's
      // estimate must not carry over into the next attempt).
      if (options_.doppler_weights) weightByDoppler(*source, cycle.mountings, estimate, dt);
      matcher.setInputSource(source);
      matcher.align(aligned_, toMatrix4<float>(estimate));
      converged = matcher.hasConverged();
      if (!converged) break;
      estimate = toPose2(matcher.getFinalTransformation());
    }
    step.attempts = attempt + 1;
    step.grid = g;
    if (converged && estimate.allFinite() && gate_.accept(estimate, guess, guess_cov, dt, motion_model_, &step.chi2)) {
      motion = estimate;
      ok = true;
      step.status = attempt == 0 ? StepStatus::Matched : StepStatus::Retried;
    }
  }
  OdometryCounters& counters = log_.counters();
  if (ok) {
    ++(step.status == StepStatus::Matched ? counters.matched : counters.retried);
  } else {
    step.status = StepStatus::Fallback;
    ++counters.fallbacks;
    motion = guess;
  }
  step.match_ms = msSince(t0);
  if (step.grid != options_.grid) matcher_.setGrid(options_.grid);
  return motion;
}

void AutomotiveOdometry::weightByDoppler(pcl::PointCloud<PointRadar>& cloud, const std::vector<SensorMounting>& mountings,
                                         const Pose2& motion, double dt) const {
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

}  // namespace radar_ndt

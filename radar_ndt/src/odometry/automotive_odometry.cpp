#include "radar_ndt/odometry/automotive_odometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "detail/run_timing.h"

namespace radar_ndt {

using detail::msSince;

AutomotiveOdometryOptions AutomotiveOdometryOptions::paper(std::size_t n) const {
  AutomotiveOdometryOptions o = *this;
  o.mode = AutomotiveMatchMode::SubmapToSubmap;
  o.submap_size = n;
  o.fuse_doppler = false;
  return o;
}

void AutomotiveOdometryOptions::validate() const {
  checkFields(*this, "AutomotiveOdometryOptions");
}

AutomotiveOdometry::AutomotiveOdometry(const AutomotiveOdometryOptions& options, MatcherAdapter matcher)
    : options_(options),
      matcher_(std::move(matcher)),
      gate_(options.gate),
      // CycleToMap needs the submap only to integrate the Doppler motion: one cycle is enough.
      submap_(options.mode == AutomotiveMatchMode::CycleToMap ? 1 : options.submap_size),
      map_(options.map_cycles),
      fusion_(options.fusion),
      car_fusion_(options.car, options.fusion) {
  options_.validate();
  // The fusion trusts a match as calibrated for the matcher that makes it.
  if (matcher_.weightedNdt())
    calibration_ = options_.doppler_weights ? MatchCalibration::Rapp : MatchCalibration::WeightedNdt;
  else
    calibration_ = matcher_.gridIsResolution() ? MatchCalibration::PclNdt : MatchCalibration::PclIcp;
}

EgoVelocity AutomotiveOdometry::egoVelocityOf(const ProcessedCycle& cycle) {
  EgoVelocity ego = cycle.ego;
  if (!ego.valid) {  // counted from the step's velocity_valid
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
  const pcl::PointCloud<PointRadar>::Ptr submap = addToSubmap(cycle, ego, dt, step);
  if (!prev) return addFirstCycle(cycle, ego, submap, step);
  const MotionEstimate prior =
      usesCar() ? carPrior(prev->timestamp_us, cycle.timestamp_us, dt, step) : dopplerPrior(dt, step);
  const MotionEstimate estimate = matchAndFuse(cycle, submap, prior, dt, step);
  step.yaw_rate_bias = usesCar() ? car_fusion_.bias() : fusion_.yawRateBias();
  step.motion = estimate.motion;
  step.pose = compose(prev->pose, estimate.motion);
  motion_model_.update(estimate.motion, dt);
  if (options_.mode == AutomotiveMatchMode::CycleToMap) map_.advance(estimate.motion, estimate.covariance);
  keepForNextMatch(cycle, estimate.motion / dt, submap);
  return log_.add(step);
}

pcl::PointCloud<PointRadar>::Ptr AutomotiveOdometry::addToSubmap(const ProcessedCycle& cycle, const EgoVelocity& ego,
                                                                 double dt, OdometryStep& step) {
  const auto t0 = detail::Clock::now();
  submap_.add(*cycle.cloud, ego.velocity, ego.covariance, dt);
  pcl::PointCloud<PointRadar>::Ptr submap = submap_.cloud();
  step.submap_ms = msSince(t0);
  return submap;
}

const OdometryStep& AutomotiveOdometry::addFirstCycle(const ProcessedCycle& cycle, const EgoVelocity& ego,
                                                      const pcl::PointCloud<PointRadar>::Ptr& submap,
                                                      OdometryStep& step) {
  step.status = StepStatus::First;
  map_.clear();
  fusion_.reset();
  car_fusion_.reset();
  keepForNextMatch(cycle, ego.velocity, submap);
  return log_.add(step);
}

MotionEstimate AutomotiveOdometry::dopplerPrior(double dt, OdometryStep& step) {
  // The Doppler motion and, fused, its bias-corrected prediction: the matcher's initial guess.
  step.prior_motion = submap_.lastMotion();
  step.prior_covariance = submap_.lastMotionCovariance();
  MotionEstimate prior{step.prior_motion, step.prior_covariance};
  if (options_.fuse_doppler) prior = fusion_.predict(step.prior_motion, step.prior_covariance, dt);
  return prior;
}

CarMotion AutomotiveOdometry::carMotion(std::int64_t t0_us, std::int64_t t1_us) const {
  const auto offset = static_cast<std::int64_t>(std::llround(options_.car.time_offset * 1e6));
  CarMotion car;
  if (options_.car.gyro && !signals_->yaw_rate.empty()) {
    car.has_yaw = true;
    car.yaw = signals_->yaw_rate.integral(t0_us + offset, t1_us + offset);
  }
  if (options_.car.wheels && !signals_->rear_wheel_rpm.empty()) {
    car.has_distance = true;
    // rpm × 2π r / 60 is m/s: the revolutions' integral times the circumference.
    car.distance = signals_->rear_wheel_rpm.integral(t0_us + offset, t1_us + offset) / 60.0 * 2.0 * kPi *
                   options_.car.wheel_radius;
  } else if (options_.car.wheels && !signals_->speed.empty()) {
    car.has_distance = true;
    car.distance = signals_->speed.integral(t0_us + offset, t1_us + offset);
  }
  return car;
}

MotionEstimate AutomotiveOdometry::carPrior(std::int64_t t0_us, std::int64_t t1_us, double dt, OdometryStep& step) {
  // The Doppler motion is still the step's record of the radar's own prior; the car's sensors
  // make the guess (with wheels and the fusion on, the Doppler translation corrects their scale).
  const Pose2 doppler = submap_.lastMotion();
  const Eigen::Matrix3d doppler_cov = submap_.lastMotionCovariance();
  const MotionEstimate prior =
      car_fusion_.predict(carMotion(t0_us, t1_us), doppler, doppler_cov, dt, options_.fuse_doppler);
  step.prior_motion = prior.motion;
  step.prior_covariance = prior.covariance;
  return prior;
}

MotionEstimate AutomotiveOdometry::matchAndFuse(const ProcessedCycle& cycle,
                                                const pcl::PointCloud<PointRadar>::Ptr& submap,
                                                const MotionEstimate& prior, double dt, OdometryStep& step) {
  // CycleToMap: the new cycle alone (the submap keeps one cycle there) against the local map;
  // SubmapToSubmap: submap to submap.
  const pcl::PointCloud<PointRadar>::Ptr& source = submap;
  const pcl::PointCloud<PointRadar>::Ptr target =
      options_.mode == AutomotiveMatchMode::CycleToMap ? map_.cloud() : target_;
  step.source_points = source->size();
  step.target_points = target ? target->size() : 0;
  if (!matcher_ || step.source_points < options_.min_points || step.target_points < options_.min_points) {
    step.status = StepStatus::DeadReckoned;
    step.too_few_points = static_cast<bool>(matcher_);
    return prior;
  }
  const std::size_t newest_begin = source->size() - cycle.cloud->size();  // the submap keeps the newest cycle last
  const Pose2 match = matchWithRetries(cycle, source, newest_begin, target, prior.motion, prior.covariance, dt, step);
  if (step.status != StepStatus::Matched && step.status != StepStatus::Retried) return prior;
  step.match_motion = match;
  step.match_covariance = matcher_.poseCovariance();
  if (options_.fuse_doppler && usesCar())
    return car_fusion_.update(match, fusion_.matchCovariance(&step.match_covariance, calibration_));
  if (options_.fuse_doppler)
    return fusion_.update(match, fusion_.matchCovariance(&step.match_covariance, calibration_));
  MotionEstimate estimate = prior;
  estimate.motion = match;
  return estimate;
}

void AutomotiveOdometry::keepForNextMatch(const ProcessedCycle& cycle, const Eigen::Vector3d& velocity,
                                          const pcl::PointCloud<PointRadar>::Ptr& submap) {
  // Rapp: the newest cycle keeps the weights its own (estimated) velocity gives it.
  if (options_.doppler_weights) submap_.newest() = weightedCycle(cycle, velocity);
  if (options_.mode == AutomotiveMatchMode::CycleToMap)
    map_.add(submap_.newest());
  else
    target_ = options_.doppler_weights ? submap_.cloud() : submap;
}

Pose2 AutomotiveOdometry::matchWithRetries(const ProcessedCycle& cycle, const pcl::PointCloud<PointRadar>::Ptr& source,
                                           std::size_t newest_begin, const pcl::PointCloud<PointRadar>::Ptr& target,
                                           const Pose2& guess, const Eigen::Matrix3d& guess_cov, double dt,
                                           OdometryStep& step) {
  const auto t0 = detail::Clock::now();
  RadarRegistration& matcher = matcher_.registration();
  Pose2 motion = guess;
  bool ok = false;
  for (int attempt = 0; attempt <= options_.max_retries && !ok; ++attempt) {
    const double g = matcher_.nominal().grid + options_.grid_step * attempt;
    if (attempt == 0)
      matcher.setInputTarget(target);  // builds the target model at the nominal grid
    else
      matcher_.apply({g, matcher_.nominal().power_shift});  // rebuilds it, enlarged
    Pose2 estimate = guess;
    const int rounds = options_.doppler_weights ? std::max(1, options_.doppler_weight_rounds) : 1;
    bool converged = false;
    for (int round = 0; round < rounds; ++round) {
      // Rapp: weights from the initial guess, then from each round's estimate (a failed attempt's
      // estimate must not carry over into the next attempt).
      if (options_.doppler_weights) weightByDoppler(*source, cycle.mountings, estimate / dt, newest_begin);
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
  if (!ok) {
    step.status = StepStatus::Fallback;
    motion = guess;
  }
  step.match_ms = msSince(t0);
  matcher_.apply(matcher_.nominal());
  return motion;
}

void AutomotiveOdometry::weightByDoppler(pcl::PointCloud<PointRadar>& cloud,
                                         const std::vector<SensorMounting>& mountings, const Eigen::Vector3d& v,
                                         std::size_t first) const {
  // Each point's Doppler against the one the velocity predicts for a stationary point there (in
  // its own cycle's frame, where it was measured).
  const double inv = 1.0 / (options_.doppler_weight_sigma * options_.doppler_weight_sigma);
  for (std::size_t i = first; i < cloud.size(); ++i) {
    PointRadar& p = cloud[i];
    double w = 0;
    if (std::isnan(p.doppler)) {
      w = 1;  // no usable Doppler: no evidence that it moves
    } else if (p.sensor_id < mountings.size() && mountings[p.sensor_id].valid) {
      const double e = p.doppler - predictedDoppler(mountings[p.sensor_id], p.x, p.y, v);
      w = std::exp(-0.5 * e * e * inv);
    }
    p.power = static_cast<float>(w);
  }
}

pcl::PointCloud<PointRadar> AutomotiveOdometry::weightedCycle(const ProcessedCycle& cycle,
                                                              const Eigen::Vector3d& velocity) const {
  pcl::PointCloud<PointRadar> c = *cycle.cloud;
  weightByDoppler(c, cycle.mountings, velocity);
  return c;
}

}  // namespace radar_ndt

#include "radar_ndt/odometry/odometry.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/LU>

#include "detail/run_timing.h"

namespace radar_ndt {

const char* toString(StepStatus s) {
  switch (s) {
    case StepStatus::First: return "first";
    case StepStatus::Matched: return "matched";
    case StepStatus::Retried: return "retried";
    case StepStatus::Fallback: return "fallback";
    case StepStatus::DeadReckoned: return "dead-reckoned";
    case StepStatus::Skipped: return "skipped";
    case StepStatus::Bridged: return "bridged";
  }
  return "?";
}

using detail::msSince;

Odometry::Odometry(const OdometryOptions& options, RadarRegistration::Ptr matcher)
    : options_(options), matcher_(std::move(matcher)), submap_(options.submap_size),
      compensated_(new pcl::PointCloud<PointRadar>) {}

void compensateMotion(const pcl::PointCloud<PointRadar>& in, const Pose2& velocity, pcl::PointCloud<PointRadar>& out) {
  if (&out != &in) out = in;
  if (out.empty()) return;
  // The pose at τ, tabulated every 0.1 ms over the scan's span of time offsets (a Cartesian scan
  // has one offset per azimuth, a few hundred distinct values) instead of a sin/cos per point.
  float t_min = std::numeric_limits<float>::infinity(), t_max = -t_min;
  for (const auto& p : out)
    if (std::isfinite(p.time_offset)) {
      t_min = std::min(t_min, p.time_offset);
      t_max = std::max(t_max, p.time_offset);
    }
  if (!(t_max >= t_min)) return;  // no finite offsets
  constexpr double kStep = 1e-4;
  const std::size_t n = static_cast<std::size_t>(std::ceil((static_cast<double>(t_max) - t_min) / kStep)) + 1;
  if (n > 100000) throw std::invalid_argument("compensateMotion: time offsets span more than 10 s");
  struct Entry {
    double c, s, tx, ty;
  };
  std::vector<Entry> table(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Pose2 T = integrateVelocity(velocity, t_min + kStep * static_cast<double>(i));
    table[i] = {std::cos(T.z()), std::sin(T.z()), T.x(), T.y()};
  }
  for (auto& p : out) {
    if (!std::isfinite(p.time_offset)) continue;
    const Entry& e = table[static_cast<std::size_t>((p.time_offset - t_min) / kStep + 0.5)];  // >= 0: round
    const double c = e.c, s = e.s, x = p.x, y = p.y;
    p.x = static_cast<float>(c * x - s * y + e.tx);
    p.y = static_cast<float>(s * x + c * y + e.ty);
    // Σ' = R Σ Rᵀ
    const double xx = p.cov_xx, xy = p.cov_xy, yy = p.cov_yy;
    p.cov_xx = static_cast<float>(c * c * xx - 2 * c * s * xy + s * s * yy);
    p.cov_xy = static_cast<float>(c * s * (xx - yy) + (c * c - s * s) * xy);
    p.cov_yy = static_cast<float>(s * s * xx + 2 * c * s * xy + c * c * yy);
    p.time_offset = 0.f;
  }
}

const OdometryStep* Odometry::previousStep() const {
  for (auto it = steps_.rbegin(); it != steps_.rend(); ++it)
    if (it->status != StepStatus::Skipped && it->status != StepStatus::Bridged) return &*it;
  return nullptr;
}

const OdometryStep& Odometry::addSkipped(OdometryStep step, const OdometryStep& prev) {
  step.status = StepStatus::Skipped;
  step.pose = prev.pose;
  ++counters_.skipped;
  steps_.push_back(step);
  return steps_.back();
}

const OdometryStep& Odometry::bridge(std::int64_t timestamp_us) {
  OdometryStep step;
  step.timestamp_us = timestamp_us;
  ++counters_.cycles;
  const OdometryStep* prev = previousStep();
  if (!prev) {  // nothing to continue from: no pose
    step.status = StepStatus::Skipped;
    ++counters_.skipped;
    steps_.push_back(step);
    return steps_.back();
  }
  if (timestamp_us <= prev->timestamp_us) return addSkipped(step, *prev);
  const double dt = 1e-6 * static_cast<double>(timestamp_us - prev->timestamp_us);
  const Eigen::Vector3d velocity = last_dt_ > 0 ? velocityOf(last_accepted_motion_, last_dt_) : Eigen::Vector3d::Zero();
  step.motion = step.doppler_motion = integrateVelocity(velocity, dt);
  step.pose = compose(prev->pose, step.motion);
  step.status = StepStatus::Bridged;
  ++counters_.bridged;
  steps_.push_back(step);
  return steps_.back();
}

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
  const OdometryStep* prev = previousStep();
  if (prev && cycle.timestamp_us <= prev->timestamp_us) return addSkipped(step, *prev);

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
  auto t0 = detail::Clock::now();
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
    t0 = detail::Clock::now();
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
        matcher_->align(aligned_, toMatrix4<float>(estimate));
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

bool Odometry::acceptScanMotion(const Pose2& motion, double dt, double mid_time) const {
  const auto& o = options_.scanning;
  if (!have_trusted_velocity_) return true;  // no accepted match yet: nothing to check against
  // The velocity of this interval (at its middle) differs from the last accepted match's (at its
  // middle) by at most a·Δt; over dt that is a displacement difference of a·Δt·dt, plus the noise
  // of two matches. Δt grows across fallbacks, so one bad estimate cannot lock the gate.
  const double elapsed = std::max(dt, mid_time - trusted_mid_time_);
  const Pose2 predicted = integrateVelocity(trusted_velocity_, dt);
  const double bound_xy = o.max_acceleration * elapsed * dt + 3.0 * std::sqrt(2.0) * o.match_sigma_xy;
  const double bound_yaw = o.max_yaw_acceleration * elapsed * dt + 3.0 * std::sqrt(2.0) * o.match_sigma_yaw;
  return (motion.head<2>() - predicted.head<2>()).norm() <= bound_xy && std::abs(normalizeAngle(motion.z() - predicted.z())) <= bound_yaw;
}

bool Odometry::acceptScanFit(double fit) const {
  const auto& o = options_.scanning;
  if (!(o.min_relative_fit > 0) || !std::isfinite(fit) || recent_fits_.size() < 5) return true;
  std::vector<double> v(recent_fits_.begin(), recent_fits_.end());
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return fit >= o.min_relative_fit * v[v.size() / 2];
}

bool Odometry::matchScan(const pcl::PointCloud<PointRadar>& raw, const Pose2& guess, const Pose2& prev_in_target, bool target_is_previous,
                         double dt, Pose2* estimate, int* rounds) {
  const auto& o = options_.scanning;
  const bool compensate = o.motion_compensation && dt > 0;
  const int max_rounds = compensate ? std::max(1, o.max_compensation_rounds) : 1;
  Pose2 est = guess;  // the motion from the previous scan
  Eigen::Vector3d v = compensate ? velocityOf(guess, dt) : Eigen::Vector3d::Zero();
  if (target_replaced_) {  // a previous attempt's re-compensated target: back to this step's own
    matcher_->setInputTarget(target_);
    target_replaced_ = false;
  }
  for (int r = 0; r < max_rounds; ++r) {
    if (compensate) {
      // Round 0: both scans at the constant-velocity estimate (the target already is). Later
      // rounds: both at the velocity this match found, which is the target sweep's own velocity
      // and the best estimate for the source's.
      // The first target was never compensated (no velocity then): it is, from round 0 on.
      if ((r > 0 || !target_compensated_) && previous_raw_ && target_is_previous) {
        pcl::PointCloud<PointRadar>::Ptr target(new pcl::PointCloud<PointRadar>);
        compensateMotion(*previous_raw_, v, *target);
        matcher_->setInputTarget(target);
        target_replaced_ = true;
      }
      compensateMotion(raw, v, *compensated_);
      matcher_->setInputSource(compensated_);
      ++*rounds;
    } else {
      // The caller's cloud is const; the matcher only reads its source.
      matcher_->setInputSource(pcl::PointCloud<PointRadar>::ConstPtr(&raw, [](const pcl::PointCloud<PointRadar>*) {}));
    }
    matcher_->align(aligned_, toMatrix4<float>(compose(prev_in_target, est)));
    if (!matcher_->hasConverged()) return false;
    est = between(prev_in_target, toPose2(matcher_->getFinalTransformation()));
    if (!est.allFinite()) return false;
    if (!compensate) break;
    const Eigen::Vector3d v_new = velocityOf(est, dt);
    // Another round only when the velocity moved by more than the tolerance (yaw rate scaled by
    // 10 m, a typical point range: the displacement it causes there). Smaller changes are within
    // a single match's noise and chasing them adds nothing.
    const bool settled = (v_new.head<2>() - v.head<2>()).norm() < o.compensation_tolerance &&
                         10.0 * std::abs(v_new.z() - v.z()) < o.compensation_tolerance;
    v = v_new;
    if (settled) break;
  }
  *estimate = est;
  return true;
}

const OdometryStep& Odometry::addScan(const ScanFrame& scan) {
  if (!scan.cloud) throw std::invalid_argument("Odometry::addScan: the scan has no cloud");
  const auto& o = options_.scanning;
  OdometryStep step;
  step.timestamp_us = scan.timestamp_us;
  ++counters_.cycles;
  const OdometryStep* prev = previousStep();
  if (prev && scan.timestamp_us <= prev->timestamp_us) return addSkipped(step, *prev);
  const pcl::PointCloud<PointRadar>& raw = *scan.cloud;
  step.source_points = raw.size();
  if (!prev) {
    // The first scan: identity. Its velocity is unknown, so it is kept uncompensated (its time
    // offsets are short against any later correction) and becomes the first target.
    step.status = StepStatus::First;
    keyframe_pose_ = Pose2::Zero();
    keyframe_stamp_us_ = scan.timestamp_us;
    previous_raw_ = scan.cloud;
    target_compensated_ = false;
    target_.reset(new pcl::PointCloud<PointRadar>(raw));
    matcher_holds_target_ = false;
    for (auto& p : *target_) p.time_offset = 0.f;
    steps_.push_back(step);
    return steps_.back();
  }

  const double dt = 1e-6 * static_cast<double>(scan.timestamp_us - prev->timestamp_us);
  const Eigen::Vector3d velocity = last_dt_ > 0 ? velocityOf(last_accepted_motion_, last_dt_) : Eigen::Vector3d::Zero();
  Pose2 guess = integrateVelocity(velocity, dt);  // constant velocity
  const double mid_time = 1e-6 * static_cast<double>(prev->timestamp_us) + 0.5 * dt;
  step.doppler_motion = guess;
  step.target_points = target_ ? target_->size() : 0;
  Pose2 motion = guess;
  bool ok = false;
  const auto t0 = detail::Clock::now();
  if (!matcher_ || step.source_points < o.min_points || step.target_points < o.min_points) {
    step.status = StepStatus::DeadReckoned;
    ++counters_.dead_reckoned;
  } else {
    // Nominal settings for this step, then the new target: one model build (settings are lazy).
    step.slow = last_dt_ > 0 && velocity.head<2>().norm() < o.slow_speed;
    const double g0 = step.slow ? o.slow_grid : o.grid;
    if (matcher_grid_ != g0) setMatcherGrid(*matcher_, matcher_grid_ = g0);
    if (matcher_shift_ != o.power_shift && setMatcherPowerShift(*matcher_, o.power_shift, o.shift_source_weights)) matcher_shift_ = o.power_shift;
    // The target model is built once per keyframe, not once per scan: while the keyframe is kept
    // the matcher still holds it (unless an attempt swapped in a re-compensated copy).
    if (!matcher_holds_target_ || target_replaced_) matcher_->setInputTarget(target_);
    matcher_holds_target_ = true;
    target_replaced_ = false;
    const bool target_is_previous = keyframe_stamp_us_ == prev->timestamp_us;
    const Pose2 prev_in_keyframe = target_is_previous ? Pose2::Zero() : between(keyframe_pose_, prev->pose);
    if (last_dt_ <= 0 && !o.start_hypotheses.empty()) {
      // No velocity yet (the second scan): zero motion may be metres off, and sensor-fixed
      // returns pull a match towards it. Start from each forward offset hypothesis and keep the
      // best-scoring result as the guess.
      double best = -std::numeric_limits<double>::infinity();
      matcher_->setInputSource(scan.cloud);
      for (const double h : o.start_hypotheses) {
        matcher_->align(aligned_, toMatrix4<float>(Pose2(h, 0, 0)));
        if (!matcher_->hasConverged()) continue;
        const Pose2 e = toPose2(matcher_->getFinalTransformation());
        const double score = matchScore(*matcher_);
        if (e.allFinite() && score > best) {
          best = score;
          guess = e;
        }
      }
      step.doppler_motion = guess;
    }
    // One attempt at the matcher's current settings from `from`: match, then the motion prior.
    auto attempt = [&](const Pose2& from, Pose2* estimate) {
      if (!matchScan(raw, from, prev_in_keyframe, target_is_previous, dt, estimate, &step.compensation_rounds)) {
        ++counters_.not_converged;
        return false;
      }
      if (!acceptScanMotion(*estimate, dt, mid_time)) {
        ++counters_.rejected;
        return false;
      }
      return true;
    };
    bool give_up = false;  // the ladder stops: a poor fit, or a retried candidate that did not hold
    for (int halving = 0; halving <= o.max_shift_halvings && !ok && !give_up; ++halving) {
      if (halving > 0) {
        const float s = o.power_shift * std::pow(0.5f, static_cast<float>(halving));
        if (!setMatcherPowerShift(*matcher_, s, o.shift_source_weights)) break;  // no power weights: nothing to halve
        matcher_shift_ = s;
      }
      for (double g = g0;; g += o.grid_step) {
        if (matcher_grid_ != g) setMatcherGrid(*matcher_, matcher_grid_ = g);
        ++step.attempts;
        step.grid = g;
        step.power_shift = matcher_shift_ < 0 ? 0.f : matcher_shift_;
        // The fit is judged at the nominal settings only (scores grow with the grid and with the
        // power shift): a scan that fits its target nowhere there is not retried, bigger cells
        // would only blur it in. Slow steps (their own small grid) are not judged.
        const bool nominal = halving == 0 && g == o.grid;
        Pose2 estimate;
        if (attempt(guess, &estimate)) {
          double fit = matchFitPerPoint(*matcher_);  // NaN: not ours, nothing to judge
          if (!nominal && !step.slow && std::isfinite(fit)) {
            // A retried candidate is where the ladder found something the motion prior allows
            // after the nominal match was refused, which is weak evidence: a bus passing
            // alongside gives one at some grid or power shift (measured on simulated drives:
            // most retried matches were wrong by 0.2-0.7 m and carried a yaw error on through
            // the fallbacks after them). It is refined at the nominal settings, where its fit can
            // be judged against recent matches, and the refined match must pass both checks;
            // otherwise the step falls back.
            setMatcherGrid(*matcher_, matcher_grid_ = o.grid);
            if (setMatcherPowerShift(*matcher_, o.power_shift, o.shift_source_weights)) matcher_shift_ = o.power_shift;
            ++step.attempts;
            const Pose2 candidate = estimate;
            if (!attempt(candidate, &estimate)) {
              give_up = true;
              break;
            }
            fit = matchFitPerPoint(*matcher_);
          }
          const bool judged = (nominal || !step.slow) && std::isfinite(fit);
          if (judged) {
            // Every judged fit enters the history, refused ones too: a scene that stays poorer
            // than the last (open land after a city centre) lowers the median within
            // fit_history / 2 scans instead of causing a fallback storm, while a passing bus
            // (a few scans) leaves the median where it was. Judged before it is added.
            const bool fits = acceptScanFit(fit);
            recent_fits_.push_back(fit);
            while (recent_fits_.size() > std::max<std::size_t>(o.fit_history, 1)) recent_fits_.pop_front();
            if (!fits) {
              ++counters_.poor_fit;
              give_up = true;
              break;
            }
          }
          motion = estimate;
          ok = true;
          break;
        }
        if (g > o.max_grid) break;
      }
    }
    if (ok) {
      trusted_velocity_ = velocityOf(motion, dt);
      trusted_mid_time_ = mid_time;
      have_trusted_velocity_ = true;
      step.status = step.attempts == 1 ? StepStatus::Matched : StepStatus::Retried;
      ++(step.status == StepStatus::Matched ? counters_.matched : counters_.retried);
      if (step.slow) ++counters_.slow;
    } else {
      step.status = StepStatus::Fallback;
      ++counters_.fallbacks;
      motion = guess;
    }
    if (matcher_shift_ >= 0 && matcher_shift_ != o.power_shift) ++counters_.shift_halved;
  }
  step.match_ms = msSince(t0);
  step.motion = motion;
  step.pose = compose(prev->pose, motion);
  last_accepted_motion_ = motion;
  last_dt_ = dt;
  // The next target: this scan at its reference time, with the velocity just estimated, unless
  // the keyframe is kept: this step matched and is close enough to it, or this step failed alone
  // (a corrupt, empty or all-noise scan must not become the target of the next one; a second
  // failure in a row means the keyframe itself no longer fits, e.g. the view changed).
  const Pose2 from_keyframe = between(keyframe_pose_, step.pose);
  const bool matched = step.status == StepStatus::Matched || step.status == StepStatus::Retried;
  consecutive_failures_ = matched ? 0 : consecutive_failures_ + 1;
  const bool keyframe_usable = target_ && target_->size() >= o.min_points;
  const bool replace = matched ? !(o.keyframe_distance > 0) || from_keyframe.head<2>().norm() >= o.keyframe_distance ||
                                     std::abs(from_keyframe.z()) >= o.keyframe_rotation
                               : consecutive_failures_ >= 2 || !keyframe_usable;
  if (replace) {
    keyframe_pose_ = step.pose;
    keyframe_stamp_us_ = step.timestamp_us;
    previous_raw_ = scan.cloud;
    target_.reset(new pcl::PointCloud<PointRadar>);
    matcher_holds_target_ = false;
    if (o.motion_compensation)
      compensateMotion(raw, velocityOf(motion, dt), *target_);
    else
      *target_ = raw;
    target_compensated_ = true;
  } else if (!target_compensated_ && o.motion_compensation && previous_raw_) {
    // The kept keyframe is the first scan: compensate it with the first velocity there is.
    target_.reset(new pcl::PointCloud<PointRadar>);
    matcher_holds_target_ = false;
    compensateMotion(*previous_raw_, velocityOf(motion, dt), *target_);
    target_compensated_ = true;
  }
  steps_.push_back(step);
  return steps_.back();
}

}  // namespace radar_ndt

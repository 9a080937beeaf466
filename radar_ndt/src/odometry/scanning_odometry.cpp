#include "radar_ndt/odometry/scanning_odometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "detail/run_timing.h"

namespace radar_ndt {

using detail::msSince;

void ScanningOdometryOptions::validate() const {
  checkFields(*this, "ScanningOdometryOptions");
}

ScanningOdometry::ScanningOdometry(const ScanningOdometryOptions& options, MatcherAdapter matcher)
    : options_(options),
      matcher_(std::move(matcher)),
      gate_(options.gate),
      keyframes_(options.keyframes),
      fits_(options.fit),
      gyro_(options.gyro),
      compensated_(new pcl::PointCloud<PointRadar>) {
  options_.validate();
  if (options_.compensation.enabled && options_.compensation.mode == CompensationMode::Joint && matcher_ &&
      !matcher_.weightedNdt())
    throw std::invalid_argument(
        "ScanningOdometry: compensation mode joint places the source's points inside the match, which only "
        "WeightedNDT2D (pw-ndt) does; use rounds with another matcher");
}

const OdometryStep& ScanningOdometry::addScan(const ScanFrame& scan) {
  if (!scan.cloud) throw std::invalid_argument("ScanningOdometry::addScan: the scan has no cloud");
  OdometryStep step = log_.begin(scan.timestamp_us);
  const OdometryStep* prev = log_.previous();
  if (prev && scan.timestamp_us <= prev->timestamp_us) return log_.addSkipped(step, *prev);
  step.source_points = scan.cloud->size();
  if (!prev) return addFirstScan(scan, step);

  const double dt = 1e-6 * static_cast<double>(scan.timestamp_us - prev->timestamp_us);
  step.prior_motion = motion_model_.predict(dt);  // constant velocity
  if (usesGyro()) gyroPrior(prev->timestamp_us, scan.timestamp_us, dt, step);
  step.target_points = target_.size();
  Pose2 motion = step.prior_motion;
  const auto t0 = detail::Clock::now();
  if (!matcher_ || step.source_points < options_.min_points || step.target_points < options_.min_points) {
    step.status = StepStatus::DeadReckoned;
    step.too_few_points = static_cast<bool>(matcher_);
  } else {
    motion = matchWithFailureHandling(scan, *prev, dt, step);
  }
  step.match_ms = msSince(t0);
  step.motion = motion;
  step.pose = compose(prev->pose, motion);
  motion_model_.update(motion, dt);
  updateKeyframe(scan, step, dt);
  return log_.add(step);
}

void ScanningOdometry::gyroPrior(std::int64_t t0_us, std::int64_t t1_us, double dt, OdometryStep& step) {
  // The translation stays the constant-velocity one; the yaw is the gyro's, bias removed.
  const auto offset = static_cast<std::int64_t>(std::llround(options_.gyro.time_offset * 1e6));
  step.prior_motion.z() = gyro_.predict(yaw_rate_->integral(t0_us + offset, t1_us + offset), dt);
}

const OdometryStep& ScanningOdometry::addFirstScan(const ScanFrame& scan, OdometryStep& step) {
  // The first scan: identity. Its velocity is unknown, so it is kept uncompensated (its time
  // offsets are short against any later correction) and becomes the first target.
  step.status = StepStatus::First;
  step.keyframe = true;
  keyframes_.reset(Pose2::Zero(), scan.timestamp_us);
  target_.resetFirst(*scan.cloud);
  return log_.add(step);
}

Pose2 ScanningOdometry::matchWithFailureHandling(const ScanFrame& scan, const OdometryStep& prev, double dt,
                                                 OdometryStep& step) {
  const ScanningOdometryOptions& o = options_;
  // Nominal settings for this step, then the new target: one model build (settings are lazy).
  step.slow = motion_model_.hasVelocity() && motion_model_.velocity().head<2>().norm() < o.slow_speed;
  const double g0 = step.slow ? o.slow_grid : matcher_.nominal().grid;
  prepareMatcher(g0);
  Attempt a;
  a.raw = scan.cloud.get();
  a.target_is_previous = keyframes_.stamp() == prev.timestamp_us;
  a.prev_in_keyframe = a.target_is_previous ? Pose2::Zero() : between(keyframes_.pose(), prev.pose);
  a.dt = dt;
  a.mid_time = 1e-6 * static_cast<double>(prev.timestamp_us) + 0.5 * dt;
  // With a gyro, the sweep turns at its (bias-corrected) mean rate over the interval.
  a.yaw_rate = usesGyro() && options_.gyro.deskew && dt > 0 ? step.prior_motion.z() / dt
                                                            : std::numeric_limits<double>::quiet_NaN();
  Pose2 guess = step.prior_motion;
  if (!motion_model_.hasVelocity() && !o.start_hypotheses.empty())
    step.prior_motion = guess = bestStartHypothesis(scan, guess);

  Pose2 motion;
  if (runRetryLadder(a, guess, g0, step, &motion)) {
    if (usesGyro()) {
      step.match_motion = motion;             // recorded before the fusion
      motion.z() = gyro_.update(motion.z());  // the match's yaw fused with the gyro's
    }
    gate_.trust(motion, dt, a.mid_time);
    step.status = step.attempts == 1 ? StepStatus::Matched : StepStatus::Retried;
  } else {
    step.status = StepStatus::Fallback;
    motion = guess;
  }
  step.shift_halved = matcher_.hasPowerWeights() && matcher_.current().power_shift != matcher_.nominal().power_shift;
  return motion;
}

void ScanningOdometry::prepareMatcher(double grid) {
  matcher_.apply({grid, matcher_.nominal().power_shift});
  target_.giveTo(matcher_.registration());
}

Pose2 ScanningOdometry::bestStartHypothesis(const ScanFrame& scan, const Pose2& guess) {
  // No velocity yet (the second scan): zero motion may be metres off, and sensor-fixed returns
  // pull a match towards it. Start from each forward offset hypothesis and keep the best-scoring
  // result as the guess.
  RadarRegistration& matcher = matcher_.registration();
  Pose2 best_guess = guess;
  double best = -std::numeric_limits<double>::infinity();
  *compensated_ = *scan.cloud;  // the matcher keeps its source: this copy, not the caller's
  matcher.setInputSource(compensated_);
  for (const double h : options_.start_hypotheses) {
    matcher.align(aligned_, toMatrix4<float>(Pose2(h, 0, guess.z())));  // the guess's yaw: the gyro's, or 0
    if (!matcher.hasConverged()) continue;
    const Pose2 e = toPose2(matcher.getFinalTransformation());
    const double score = matcher_.score();
    if (e.allFinite() && score > best) {
      best = score;
      best_guess = e;
    }
  }
  return best_guess;
}

bool ScanningOdometry::runRetryLadder(const Attempt& a, const Pose2& guess, double nominal_grid, OdometryStep& step,
                                      Pose2* motion) {
  const ScanningOdometryOptions& o = options_;
  const MatchSettings nominal_settings = matcher_.nominal();
  for (int halving = 0; halving <= o.max_shift_halvings; ++halving) {
    if (halving > 0 && !matcher_.hasPowerWeights()) return false;  // nothing to halve
    const float shift = nominal_settings.power_shift * std::pow(0.5f, static_cast<float>(halving));
    for (double g = nominal_grid;; g += o.grid_step) {
      matcher_.apply({g, shift});
      ++step.attempts;
      step.grid = g;
      step.power_shift = matcher_.current().power_shift;
      const bool nominal = halving == 0 && g == nominal_settings.grid;
      Pose2 estimate;
      if (attempt(a, guess, step, &estimate)) {
        // The fit is judged at the nominal settings only (scores grow with the grid and with the
        // power shift): a scan that fits its target nowhere there is not retried, bigger cells
        // would only blur it in. Slow steps (their own small grid) are not judged.
        if (!nominal && !step.slow && std::isfinite(matcher_.fitPerPoint()) && !refineAtNominal(a, step, &estimate))
          return false;
        if (!fitsLikeRecentMatches(nominal || !step.slow, step)) return false;
        *motion = estimate;
        return true;
      }
      if (g > o.max_grid) break;
    }
  }
  return false;
}

bool ScanningOdometry::refineAtNominal(const Attempt& a, OdometryStep& step, Pose2* estimate) {
  // A retried candidate is where the ladder found something the motion prior allows after the
  // nominal match was refused, which is weak evidence: a bus passing alongside gives one at some
  // grid or power shift, usually wrong by decimetres and with a yaw error the fallbacks after it
  // carry on. It is refined at the nominal settings, where its fit can be judged against recent
  // matches, and the refined match must pass both checks; otherwise the step falls back.
  matcher_.apply(matcher_.nominal());
  ++step.attempts;
  const Pose2 candidate = *estimate;
  return attempt(a, candidate, step, estimate);
}

bool ScanningOdometry::fitsLikeRecentMatches(bool judged, OdometryStep& step) {
  const double fit = matcher_.fitPerPoint();  // NaN: not WeightedNDT2D, nothing to judge
  if (!judged || !std::isfinite(fit)) return true;
  // Judged before it enters the history (FitHistory: refused fits enter it too).
  const bool fits = fits_.accepts(fit);
  fits_.add(fit);
  if (!fits) ++step.attempts_poor_fit;
  return fits;
}

bool ScanningOdometry::attempt(const Attempt& a, const Pose2& from, OdometryStep& step, Pose2* estimate) {
  if (!matchScan(a, from, estimate, &step.compensation_rounds)) {
    ++step.attempts_not_converged;
    return false;
  }
  if (!gate_.accept(*estimate, a.dt, a.mid_time)) {
    ++step.attempts_rejected;
    return false;
  }
  return true;
}

bool ScanningOdometry::matchScan(const Attempt& a, const Pose2& guess, Pose2* estimate, int* rounds) {
  const MotionCompensationOptions& c = options_.compensation;
  RadarRegistration& matcher = matcher_.registration();
  const bool compensate = c.enabled && a.dt > 0;
  const int max_rounds = compensate ? std::max(1, c.max_rounds) : 1;
  Pose2 est = guess;  // the motion from the previous scan
  Eigen::Vector3d v = compensate ? velocityOf(guess, a.dt) : Eigen::Vector3d::Zero();
  const bool gyro_rate = compensate && std::isfinite(a.yaw_rate);
  if (gyro_rate) v.z() = a.yaw_rate;
  target_.restore(matcher);  // a previous attempt's re-compensated target: back to this step's own
  // Joint: the source as given, its points placed inside the match by the motion being estimated
  // (from the previous scan, at prev_in_keyframe, over dt); only the target is compensated here.
  const bool joint = compensate && c.mode == CompensationMode::Joint;
  struct SweepScope {  // the matcher is rigid again whatever way this returns
    MatcherAdapter::WeightedNdt* weighted_ndt;
    ~SweepScope() {
      if (weighted_ndt) weighted_ndt->clearSourceSweep();
    }
  } sweep{joint ? matcher_.weightedNdt() : nullptr};
  if (joint) {
    sweep.weighted_ndt->setSourceSweep(a.dt, a.prev_in_keyframe);
    *compensated_ = *a.raw;
    matcher.setInputSource(compensated_);
  }
  for (int r = 0; r < max_rounds; ++r) {
    if (compensate) {
      // Round 0: both scans at the constant-velocity estimate (the target already is). Later
      // rounds: both at the velocity this match found, which is the target sweep's own velocity
      // and the best estimate for the source's.
      // The first target was never compensated (no velocity then): it is, from round 0 on.
      if ((r > 0 || !target_.compensated()) && a.target_is_previous) target_.giveRecompensated(matcher, v);
      if (!joint) {
        compensateMotion(*a.raw, v, *compensated_);
        matcher.setInputSource(compensated_);
      }
      ++*rounds;
    } else {
      *compensated_ = *a.raw;  // the matcher keeps its source: this copy, not the caller's
      matcher.setInputSource(compensated_);
    }
    matcher.align(aligned_, toMatrix4<float>(compose(a.prev_in_keyframe, est)));
    if (!matcher.hasConverged()) return false;
    est = between(a.prev_in_keyframe, toPose2(matcher.getFinalTransformation()));
    if (!est.allFinite()) return false;
    if (!compensate) break;
    Eigen::Vector3d v_new = velocityOf(est, a.dt);
    if (gyro_rate) v_new.z() = a.yaw_rate;  // the measured rotation, not the match's
    // Another round only when the velocity moved by more than the tolerance (yaw rate scaled by
    // 10 m, a typical point range: the displacement it causes there). Smaller changes are within
    // a single match's noise and chasing them adds nothing.
    const bool settled =
        (v_new.head<2>() - v.head<2>()).norm() < c.tolerance && 10.0 * std::abs(v_new.z() - v.z()) < c.tolerance;
    v = v_new;
    if (settled) break;
  }
  *estimate = est;
  return true;
}

void ScanningOdometry::updateKeyframe(const ScanFrame& scan, OdometryStep& step, double dt) {
  // The next target: this scan at its reference time, with the velocity just estimated, unless
  // the keyframe is kept (KeyframePolicy).
  const bool matched = step.status == StepStatus::Matched || step.status == StepStatus::Retried;
  const bool keyframe_usable = target_.cloud() && target_.size() >= options_.min_points;
  const bool compensate = options_.compensation.enabled;
  const Eigen::Vector3d velocity = velocityOf(step.motion, dt);
  if (keyframes_.replaceAfter(matched, step.pose, keyframe_usable)) {
    step.keyframe = true;
    keyframes_.reset(step.pose, step.timestamp_us);
    target_.reset(*scan.cloud, compensate ? &velocity : nullptr);
  } else if (compensate) {
    target_.compensateFirst(velocity);  // the kept keyframe is the first scan: once a velocity is known
  }
}

}  // namespace radar_ndt

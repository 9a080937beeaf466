#include "radar_ndt/odometry/odometry_step.h"

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

void countStep(const OdometryStep& s, OdometryCounters& c) {
  ++c.cycles;
  switch (s.status) {
    case StepStatus::First: ++c.first; break;
    case StepStatus::Matched: ++c.matched; break;
    case StepStatus::Retried: ++c.retried; break;
    case StepStatus::Fallback: ++c.fallbacks; break;
    case StepStatus::DeadReckoned: ++c.dead_reckoned; break;
    case StepStatus::Skipped: ++c.skipped; break;
    case StepStatus::Bridged: ++c.bridged; break;
  }
  const bool matched = s.status == StepStatus::Matched || s.status == StepStatus::Retried;
  if (s.status == StepStatus::DeadReckoned && s.too_few_points) ++c.too_few_points;
  if (matched && s.slow) ++c.slow;
  if (s.shift_halved) ++c.shift_halved;
  if (!s.velocity_valid) ++c.stale_velocity;
  c.not_converged += static_cast<std::size_t>(s.attempts_not_converged);
  c.rejected += static_cast<std::size_t>(s.attempts_rejected);
  c.poor_fit += static_cast<std::size_t>(s.attempts_poor_fit);
}

OdometryStep StepLog::begin(std::int64_t timestamp_us) {
  OdometryStep step;
  step.timestamp_us = timestamp_us;
  return step;
}

const OdometryStep* StepLog::previous() const {
  for (auto it = steps_.rbegin(); it != steps_.rend(); ++it)
    if (it->status != StepStatus::Skipped && it->status != StepStatus::Bridged) return &*it;
  return nullptr;
}

const OdometryStep& StepLog::add(const OdometryStep& step) {
  steps_.push_back(step);
  countStep(step, counters_);
  return steps_.back();
}

const OdometryStep& StepLog::addSkipped(OdometryStep step, const OdometryStep& prev) {
  step.status = StepStatus::Skipped;
  step.pose = prev.pose;
  return add(step);
}

const OdometryStep& StepLog::bridge(std::int64_t timestamp_us, const ConstantVelocityModel& model) {
  OdometryStep step = begin(timestamp_us);
  const OdometryStep* prev = previous();
  if (!prev) {  // nothing to continue from: no pose
    step.status = StepStatus::Skipped;
    return add(step);
  }
  if (timestamp_us <= prev->timestamp_us) return addSkipped(step, *prev);
  const double dt = 1e-6 * static_cast<double>(timestamp_us - prev->timestamp_us);
  step.motion = step.prior_motion = model.predict(dt);
  step.pose = compose(prev->pose, step.motion);
  step.status = StepStatus::Bridged;
  return add(step);
}

Trajectory StepLog::trajectory() const {
  Trajectory t;
  for (const auto& s : steps_) {
    if (s.status == StepStatus::Skipped) continue;
    t.stamps.push_back(1e-6 * static_cast<double>(s.timestamp_us));
    t.poses.push_back(toIsometry3(s.pose));
  }
  return t;
}

}  // namespace radar_ndt

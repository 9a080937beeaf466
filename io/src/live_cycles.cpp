#include "radar_ndt/io/live_cycles.h"

#include <algorithm>

namespace radar_ndt {

std::int64_t LiveCycles::periodUs() const {
  if (fixed_period_us_ > 0) return fixed_period_us_;
  if (intervals_.empty()) return 1;
  std::vector<std::int64_t> v = intervals_;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return std::max<std::int64_t>(1, v[v.size() / 2]);
}

LiveCycles::Added LiveCycles::add(RadarSweepData sweep) {
  const std::int64_t t = sweep.timestamp_us;
  first_us_ = first_us_ < 0 ? t : std::min(first_us_, t);
  if (last_out_us_ >= 0 && t <= last_out_us_ && !(t == last_out_us_ && sweep.sensor_id != reference_))
    return Added::Late;
  auto& mine = sweeps_[sweep.sensor_id];
  // Kept in time order; a second sweep of a radar at the same time is a repeat.
  auto at = std::upper_bound(mine.begin(), mine.end(), t,
                             [](std::int64_t v, const RadarSweepData& s) { return v < s.timestamp_us; });
  if (at != mine.begin() && std::prev(at)->timestamp_us == t) return Added::Repeated;
  if (sweep.sensor_id == reference_) {
    if (last_reference_us_ >= 0 && t > last_reference_us_) intervals_.push_back(t - last_reference_us_);
    if (intervals_.size() > 200) intervals_.erase(intervals_.begin());
    last_reference_us_ = std::max(last_reference_us_, t);
    pending_.insert(std::upper_bound(pending_.begin(), pending_.end(), t), t);
  }
  mine.insert(at, std::move(sweep));
  return Added::Taken;
}

bool LiveCycles::complete(std::int64_t t_ref) const {
  // Every other radar has sent a sweep after t_ref, so none of the cycle's can still be on the way;
  // a radar silent for a second of the stream's time (the reference's newest sweep) is not waited
  // for, nor an expected one that has not spoken in the stream's first second.
  for (const std::uint16_t channel : expected_) {
    const auto it = sweeps_.find(channel);
    if (channel != reference_ && (it == sweeps_.end() || it->second.empty()) &&
        last_reference_us_ - first_us_ < kSilenceUs)
      return false;
  }
  for (const auto& [channel, list] : sweeps_)
    if (channel != reference_ && !list.empty() && list.back().timestamp_us <= t_ref &&
        last_reference_us_ - list.back().timestamp_us < kSilenceUs)
      return false;
  return true;
}

RadarCycle LiveCycles::assemble(std::int64_t t_ref) const {
  RadarCycle cycle;
  cycle.timestamp_us = t_ref;
  const std::int64_t period = periodUs();
  for (const auto& [channel, list] : sweeps_) {  // channel order, as planRadarCycles' members
    const RadarSweepData* pick = nullptr;
    for (const RadarSweepData& s : list)
      if (s.timestamp_us <= t_ref && s.timestamp_us > t_ref - period) pick = &s;
    if (channel == reference_)
      for (const RadarSweepData& s : list)
        if (s.timestamp_us == t_ref) pick = &s;
    if (pick) cycle.sweeps.push_back(*pick);
  }
  return cycle;
}

void LiveCycles::forgetBefore(std::int64_t t_us) {
  // Keep a second's worth before the cycle handed out: the next cycles' windows reach back one period.
  for (auto& [channel, list] : sweeps_)
    while (list.size() > 1 && list.front().timestamp_us < t_us - 1000000) list.pop_front();
}

std::optional<RadarCycle> LiveCycles::next() {
  if (pending_.empty() || !complete(pending_.front())) return std::nullopt;
  const std::int64_t t_ref = pending_.front();
  pending_.pop_front();
  RadarCycle c = assemble(t_ref);
  last_out_us_ = t_ref;
  forgetBefore(t_ref);
  return c;
}

std::vector<RadarCycle> LiveCycles::flush() {
  std::vector<RadarCycle> out;
  while (!pending_.empty()) {
    out.push_back(assemble(pending_.front()));
    last_out_us_ = pending_.front();
    pending_.pop_front();
  }
  return out;
}

void LiveCycles::reset() {
  sweeps_.clear();
  pending_.clear();
  intervals_.clear();
  last_reference_us_ = last_out_us_ = first_us_ = -1;
}

}  // namespace radar_ndt

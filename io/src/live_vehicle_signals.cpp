#include "radar_ndt/io/live_vehicle_signals.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace radar_ndt {

LiveVehicleSignals::LiveVehicleSignals(std::string source, std::vector<Signal> in_use)
    : source_(std::move(source)), in_use_(std::move(in_use)) {
  reset();
}

void LiveVehicleSignals::reset() {
  signals_ = std::make_shared<VehicleSignals>();
  signals_->source = source_;
  used_us_ = std::numeric_limits<std::int64_t>::min();
}

LiveVehicleSignals::Added LiveVehicleSignals::add(Signal signal, std::int64_t t_us, double value) {
  if (!std::isfinite(value)) {
    ++signals_->dropped;
    return Added::NotFinite;
  }
  if (t_us <= used_us_) return Added::Late;
  TimeSeries& s = series(signal);
  // Mostly appended; a message out of order goes to its place. A stamp already there keeps its
  // first value (the offline reader's stable sort, then the first of equal stamps).
  const auto it = std::lower_bound(s.stamps_us.begin(), s.stamps_us.end(), t_us);
  if (it != s.stamps_us.end() && *it == t_us) return Added::Repeated;
  const auto i = std::distance(s.stamps_us.begin(), it);
  s.stamps_us.insert(it, t_us);
  s.values.insert(s.values.begin() + i, value);
  return Added::Taken;
}

bool LiveVehicleSignals::reaches(std::int64_t t_us, std::int64_t stream_us) const {
  for (const Signal signal : in_use_) {
    const TimeSeries& s = series(signal);
    if (!s.empty() && s.stamps_us.back() >= t_us) continue;
    const std::int64_t last = s.empty() ? std::numeric_limits<std::int64_t>::min() / 2 : s.stamps_us.back();
    if (stream_us - std::max(last, t_us) <= kSilenceUs) return false;
  }
  return true;
}

void LiveVehicleSignals::used(std::int64_t t_us) {
  used_us_ = std::max(used_us_, t_us);
  for (const Signal signal : in_use_) {
    TimeSeries& s = series(signal);
    // The next integral starts at t_us: it needs the last sample at or before it, nothing earlier.
    const auto it = std::upper_bound(s.stamps_us.begin(), s.stamps_us.end(), used_us_);
    if (it == s.stamps_us.begin()) continue;
    const auto n = std::distance(s.stamps_us.begin(), it) - 1;
    s.stamps_us.erase(s.stamps_us.begin(), s.stamps_us.begin() + n);
    s.values.erase(s.values.begin(), s.values.begin() + n);
  }
}

}  // namespace radar_ndt

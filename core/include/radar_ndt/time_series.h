#pragma once
// A scalar signal sampled at increasing times (a car's yaw rate, a wheel's speed), read as the
// pipelines need it: its value at a time and its integral over an interval, both of the signal's
// linear interpolation. Beyond its first and last samples the signal holds its end values, so an
// interval that reaches past the recording is integrated, not refused (the caller can ask covers()).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace radar_ndt {

struct TimeSeries {
  std::vector<std::int64_t> stamps_us;  ///< increasing
  std::vector<double> values;           ///< one per stamp

  bool empty() const { return stamps_us.empty(); }
  std::size_t size() const { return stamps_us.size(); }
  /// Whether [t0, t1] lies within the first and last samples.
  bool covers(std::int64_t t0_us, std::int64_t t1_us) const {
    return !empty() && t0_us >= stamps_us.front() && t1_us <= stamps_us.back();
  }
  /// The linear interpolation at `t_us` (the end value beyond the ends); 0 when empty.
  double at(std::int64_t t_us) const {
    if (empty()) return 0.0;
    if (t_us <= stamps_us.front()) return values.front();
    if (t_us >= stamps_us.back()) return values.back();
    const std::size_t i = static_cast<std::size_t>(std::upper_bound(stamps_us.begin(), stamps_us.end(), t_us) -
                                                   stamps_us.begin());  // stamps[i-1] <= t < stamps[i]
    const double a =
        static_cast<double>(t_us - stamps_us[i - 1]) / static_cast<double>(stamps_us[i] - stamps_us[i - 1]);
    return values[i - 1] + a * (values[i] - values[i - 1]);
  }
  /// ∫ from t0 to t1 of the interpolation, in value × seconds (negative when t1 < t0); 0 when empty.
  double integral(std::int64_t t0_us, std::int64_t t1_us) const {
    if (empty() || t0_us == t1_us) return 0.0;
    if (t1_us < t0_us) return -integral(t1_us, t0_us);
    // The trapezoids between t0, the samples strictly inside (t0, t1) and t1.
    auto it = std::upper_bound(stamps_us.begin(), stamps_us.end(), t0_us);
    std::int64_t t_prev = t0_us;
    double v_prev = at(t0_us), sum = 0.0;
    for (; it != stamps_us.end() && *it < t1_us; ++it) {
      const double v = values[static_cast<std::size_t>(it - stamps_us.begin())];
      sum += 0.5 * (v_prev + v) * 1e-6 * static_cast<double>(*it - t_prev);
      t_prev = *it;
      v_prev = v;
    }
    return sum + 0.5 * (v_prev + at(t1_us)) * 1e-6 * static_cast<double>(t1_us - t_prev);
  }
  /// The mean over [t0, t1]: integral / duration; the value at t0 for an empty interval.
  double mean(std::int64_t t0_us, std::int64_t t1_us) const {
    return t1_us == t0_us ? at(t0_us) : integral(t0_us, t1_us) / (1e-6 * static_cast<double>(t1_us - t0_us));
  }
};

}  // namespace radar_ndt

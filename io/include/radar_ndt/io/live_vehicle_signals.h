#pragma once
// The car's own signals as messages arrive (the ROS node's): the gyro's yaw rate and the speed the
// odometry integrates between cycles (AutomotiveOdometry::setVehicleSignals), each grown message by
// message as the offline reader builds it from a whole bag (sorted by stamp, a repeated stamp's
// first value kept, NaN left out). A cycle may be matched once every signal in use reaches past
// its time: the integral to it then holds the samples the offline run's does, and the
// interpolation at its end the same two. A signal silent for a second of the stream's time is not
// waited for (the series holds its last value, as offline past its end).

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "radar_ndt/io/vehicle_signals.h"

namespace radar_ndt {

class LiveVehicleSignals {
 public:
  enum class Signal { YawRate, Speed };
  /// The signals in use (a cycle waits for each); `source` names them in messages.
  explicit LiveVehicleSignals(std::string source = "imu", std::vector<Signal> in_use = {Signal::YawRate});

  enum class Added { Taken, Late, Repeated, NotFinite };
  /// A sample of `signal` at `t_us` (the car's clock: the radar's plus the time offset). Late: at
  /// or before a time the odometry has already integrated to (used()), so it cannot be taken into
  /// account.
  Added add(Signal signal, std::int64_t t_us, double value);

  /// Whether a cycle whose integral ends at `t_us` can be matched: for every signal in use, a
  /// sample at or after it has arrived, or the signal has been silent for over a second of the
  /// stream, whose newest time (any message's) is `stream_us`.
  bool reaches(std::int64_t t_us, std::int64_t stream_us) const;

  /// The odometry integrated to `t_us`: later samples before it are late; samples no later
  /// integral needs (all before `t_us` but the last one) are forgotten.
  void used(std::int64_t t_us);

  /// The series, for AutomotiveOdometry::setVehicleSignals (they grow as samples are added).
  std::shared_ptr<const VehicleSignals> signals() const { return signals_; }
  /// Forgets every sample (the stream's time jumped back); new series, so an odometry holding
  /// the old ones is unaffected.
  void reset();

 private:
  static constexpr std::int64_t kSilenceUs = 1000000;
  TimeSeries& series(Signal s) { return s == Signal::YawRate ? signals_->yaw_rate : signals_->speed; }
  const TimeSeries& series(Signal s) const { return s == Signal::YawRate ? signals_->yaw_rate : signals_->speed; }

  std::string source_;
  std::vector<Signal> in_use_;
  std::shared_ptr<VehicleSignals> signals_;
  std::int64_t used_us_ = std::numeric_limits<std::int64_t>::min();
};

}  // namespace radar_ndt

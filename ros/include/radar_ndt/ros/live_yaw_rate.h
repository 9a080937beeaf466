#pragma once
// The car's gyro as IMU messages arrive (the ROS node's): the yaw-rate series the automotive
// odometry integrates between cycles (AutomotiveOdometry::setVehicleSignals), grown message by
// message, as the offline run builds it from a whole bag (sorted by stamp, a repeated stamp's first
// value kept, NaN left out). A cycle may be matched once the series reaches past its time: the
// integral to it then holds the samples the offline run's does, and the interpolation at its end
// the same two. A gyro silent for a second of the stream's time is not waited for (the series
// holds its last value, as offline past its end).

#include <cstdint>
#include <limits>
#include <memory>

#include "radar_ndt/io/vehicle_signals.h"

namespace radar_ndt {
namespace ros1 {

class LiveYawRate {
 public:
  explicit LiveYawRate(std::string source = "imu");

  enum class Added { Taken, Late, Repeated, NotFinite };
  /// A sample at `t_us` (the gyro's clock: the radar's plus the time offset). Late: at or before a
  /// time the odometry has already integrated to (used()), so it cannot be taken into account.
  Added add(std::int64_t t_us, double rate);

  /// Whether a cycle whose integral ends at `t_us` can be matched: a sample at or after it has
  /// arrived, or the gyro has been silent for over a second of the stream, whose newest time (any
  /// message's) is `stream_us`.
  bool reaches(std::int64_t t_us, std::int64_t stream_us) const;

  /// The odometry integrated to `t_us`: later samples before it are late; samples no later
  /// integral needs (all before `t_us` but the last one) are forgotten.
  void used(std::int64_t t_us);

  /// The series, for AutomotiveOdometry::setVehicleSignals (it grows as samples are added).
  std::shared_ptr<const VehicleSignals> signals() const { return signals_; }
  /// Forgets every sample (the stream's time jumped back); a new series, so an odometry holding
  /// the old one is unaffected.
  void reset();

  std::int64_t newest() const;

 private:
  static constexpr std::int64_t kSilenceUs = 1000000;
  std::string source_;
  std::shared_ptr<VehicleSignals> signals_;
  std::int64_t used_us_ = std::numeric_limits<std::int64_t>::min();
};

}  // namespace ros1
}  // namespace radar_ndt

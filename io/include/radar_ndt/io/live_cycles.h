#pragma once
// Radar cycles from sweeps as they arrive (the ROS node's), planned as planRadarCycles plans a
// whole recording: the reference radar clocks the cycles, each other radar gives its latest sweep
// with t_ref − period < t ≤ t_ref. A cycle is handed out once every other radar has sent a sweep
// after it (so none of its sweeps can still be on the way), or on flush(). A radar silent for a
// second of the stream's time is not waited for; nor is one that has not spoken since the stream
// began, once it has run a second (an expected radar that never sends). Sweeps older than the last
// cycle handed out are late: refused, for the caller to say so.

#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <vector>

#include "radar_ndt/io/radar_cycle.h"

namespace radar_ndt {

class LiveCycles {
 public:
  /// `period_us` > 0: the window the offline planner would use (the median of the reference's
  /// intervals over the recording); 0: the running median of the intervals seen so far.
  /// `expected`: the radars the cycles wait for before they have spoken (the first cycles of a
  /// stream hold the sweeps the offline planner's do, whichever radar's message arrives first);
  /// radars not listed are waited for once they have spoken.
  LiveCycles(std::uint16_t reference_channel, std::int64_t period_us = 0, std::vector<std::uint16_t> expected = {})
      : reference_(reference_channel), fixed_period_us_(period_us), expected_(std::move(expected)) {}

  enum class Added { Taken, Late, Repeated };
  Added add(RadarSweepData sweep);

  /// The next cycle that is complete, oldest first.
  std::optional<RadarCycle> next();
  /// Every pending cycle, complete or not (end of the stream).
  std::vector<RadarCycle> flush();
  /// Forgets everything (the stream's time jumped back: a bag played in a loop).
  void reset();

  std::int64_t lastHandedOut() const { return last_out_us_; }
  std::int64_t periodUs() const;

 private:
  RadarCycle assemble(std::int64_t t_ref) const;
  bool complete(std::int64_t t_ref) const;
  void forgetBefore(std::int64_t t_us);

  static constexpr std::int64_t kSilenceUs = 1000000;
  std::uint16_t reference_;
  std::int64_t fixed_period_us_;
  std::vector<std::uint16_t> expected_;
  std::map<std::uint16_t, std::deque<RadarSweepData>> sweeps_;  ///< per channel, time order
  std::deque<std::int64_t> pending_;                            ///< reference times not yet handed out
  std::vector<std::int64_t> intervals_;                         ///< the reference's, for the running median
  std::int64_t last_reference_us_ = -1, last_out_us_ = -1;
  std::int64_t first_us_ = -1;  ///< the first sweep's time since the start (or reset)
};

}  // namespace radar_ndt

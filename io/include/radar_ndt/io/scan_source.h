#pragma once
// Where a scanning run's scans come from: a dataset folder (ScanningSequence) or a ROS bag's polar
// images (ros/include/radar_ndt/ros/rosbag_scans.h). The run asks for scans by index, on several
// threads at once, and for what the recording holds beside them (ground truth, a gyro).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/io/vehicle_signals.h"

namespace radar_ndt {

class ScanSource {
 public:
  virtual ~ScanSource() = default;
  virtual std::size_t size() const = 0;
  /// Scan k's reference time (µs), increasing with k.
  virtual std::int64_t stamp(std::size_t k) const = 0;
  /// Where scan k comes from, for messages: its file, or its bag, topic and time.
  virtual std::string scanName(std::size_t k) const = 0;
  /// Decodes scan k; called from several threads at once. Throws IoError naming scanName(k).
  virtual PolarScan load(std::size_t k) const = 0;
  /// Median interval between scans (s).
  virtual double periodSeconds() const = 0;
  virtual const std::string& name() const = 0;
  /// The layout's name for results: oxford, radiate, boreas, rosbag.
  virtual std::string formatName() const = 0;
  /// SE(2) ground truth in the vehicle frame, seconds; empty when the recording has none.
  virtual const Trajectory& groundTruth() const = 0;
  /// Parts of the recording that were left out, each naming where and why.
  virtual const std::vector<std::string>& indexProblems() const = 0;
  /// The recording's yaw-rate gyro; none, with the reason in `why_not` (a sentence naming the
  /// file or topic), when it has none.
  virtual std::optional<VehicleSignals> gyro(std::string* why_not) const = 0;
};

}  // namespace radar_ndt

#pragma once
// A recording read through a sensor description (a ROS 1 bag): point-cloud radars as radar cycles
// with the car's own signals, or one scanning radar's polar scans. io knows no recording format
// itself: a reader registers its format's name (ros/: ros1::registerBagReader() for "rosbag"), so
// the run entry (radar_ndt/pipeline/odometry_run.h) opens a recording by its name without depending
// on ROS, and a build without ROS says so when one is asked for.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "radar_ndt/io/imu_sample.h"
#include "radar_ndt/io/radar_cycle.h"
#include "radar_ndt/io/scan_source.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/io/vehicle_signals.h"

namespace radar_ndt {

struct Recording {
  /// Point-cloud radars: their cycles (null for a scanning radar).
  std::unique_ptr<const RadarCycleSource> cycles;
  /// The car's own gyro and speed where the description names their topics (point-cloud radars).
  std::shared_ptr<const VehicleSignals> car;
  /// The rig's 6-axis IMU in the base frame's axes, time-ordered, where the description names its
  /// topic (point-cloud radars): what the 6-DoF pipeline fuses.
  std::vector<ImuSample> imu;
  /// What reading the recording met, said once each (point-cloud radars; a scan source keeps its own).
  std::vector<std::string> problems;
  /// A scanning radar: its polar scans (null for point-cloud radars).
  std::unique_ptr<const ScanSource> scans;
};

/// Reads `path` as `sensors` describes it; throws IoError naming the file and the problem.
using RecordingReader = std::function<Recording(const std::string& path, const SensorDescription& sensors)>;

/// Makes `reader` the one for `format` (replacing an earlier one).
void registerRecordingReader(const std::string& format, RecordingReader reader);
/// Whether a reader of `format` is registered.
bool hasRecordingReader(const std::string& format);
/// Reads `path` with `format`'s reader; std::invalid_argument when none is registered (a build
/// without ROS support for "rosbag").
Recording readRecording(const std::string& format, const std::string& path, const SensorDescription& sensors);

}  // namespace radar_ndt

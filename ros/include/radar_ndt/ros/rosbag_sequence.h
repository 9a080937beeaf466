#pragma once
// A ROS 1 bag as radar cycles (docs/ros.md): the topics a sensor description names, read with
// Debian's rosbag library (bag format 2.0; chunks uncompressed, bz2 or lz4), planned into cycles
// as a nuScenes scene is (the reference radar clocks them; each other radar gives its latest sweep
// within one period before), with the vehicle's IMU and ground truth when the description names
// them. The bag is read once, when constructed; the cycles are then served from memory.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "radar_ndt/io/imu_sample.h"
#include "radar_ndt/io/radar_cycle.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/io/vehicle_signals.h"

namespace radar_ndt {
namespace ros1 {

/// What reading a bag met, beyond the cycles.
struct BagReadStats {
  std::size_t radar_messages = 0;
  std::size_t unreadable_messages = 0;  ///< malformed clouds, left out (each in problems())
  std::size_t non_finite_dropped = 0;   ///< points with NaN or Inf values, dropped
  std::size_t imu_messages = 0;
  std::size_t ground_truth_poses = 0;
};

class RosbagRadarSequence : public RadarCycleSource {
 public:
  /// Reads `bag_path` as `sensors` describes it. Throws IoError naming the bag and the problem: no
  /// such file, not a bag, truncated, unindexed (then: run `rosbag reindex`), a described topic
  /// missing or of the wrong message type, a radar none of whose messages could be read, a radar
  /// without a mounting.
  RosbagRadarSequence(const std::string& bag_path, const SensorDescription& sensors);

  const std::string& sceneName() const override { return name_; }
  const std::string& referenceChannel() const override { return reference_channel_; }
  double periodSeconds() const override { return period_s_; }
  std::size_t size() const override { return plans_.size(); }
  std::int64_t timestamp(std::size_t k) const override { return sweeps_[plans_[k].reference].timestamp_us; }
  Trajectory groundTruthTrajectory() const override;
  Trajectory groundTruth6Dof() const override { return ground_truth_; }
  const std::vector<std::string>& silences() const override { return silences_; }
  RadarCycle load(std::size_t k, std::vector<std::string>* problems = nullptr,
                  std::size_t* non_finite_dropped = nullptr) const override;

  /// The radars' names (channel index → name), in the description's order.
  const std::vector<std::string>& channels() const { return channels_; }
  /// The vehicle's yaw rate from the IMU topic (no wheel speeds); null without an IMU topic.
  std::shared_ptr<const VehicleSignals> vehicleSignals() const { return signals_; }
  /// The IMU's messages as 6-axis readings turned into the base frame's axes (`imu_mounting`), at
  /// the description's stamps, in the bag's order; those with a non-finite value left out. Empty
  /// without an IMU topic.
  const std::vector<ImuSample>& imuSamples() const { return imu_; }
  /// The ground truth as read (vehicle poses in the parent frame, stamped), before planning.
  const Trajectory& groundTruthPoses() const { return ground_truth_; }
  /// What reading met that concerns the whole bag (stamps taken from receive times, messages left
  /// out, ground-truth poses missing), each said once.
  const std::vector<std::string>& problems() const { return problems_; }
  const BagReadStats& stats() const { return stats_; }

 private:
  struct Sweep {
    std::int64_t timestamp_us = 0;
    std::uint16_t channel = 0;
    pcl::PointCloud<PointRadar> points;
    std::size_t non_finite = 0;
  };
  std::string path_, name_, reference_channel_;
  double period_s_ = 0;
  std::vector<std::string> channels_;
  std::vector<Eigen::Isometry3d> mountings_;  ///< channel → sensor to vehicle
  std::vector<Sweep> sweeps_;
  std::vector<CyclePlan> plans_;
  std::vector<std::string> silences_, problems_;
  std::shared_ptr<const VehicleSignals> signals_;
  std::vector<ImuSample> imu_;
  Trajectory ground_truth_;
  BagReadStats stats_;
  friend class BagReader;
};

}  // namespace ros1
}  // namespace radar_ndt

#pragma once
// Automotive radar cycles as a dataset gives them: one sweep of every radar, clocked by a
// reference radar (the cycle's time is the reference sweep's), each sweep's points in its sensor
// frame with the sensor's mounting beside them. Planning which sweeps form a cycle is dataset
// access; turning a cycle into one cloud is the front-end's (frontend/automotive_front_end.h).

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>

#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/point_types.h"

namespace radar_ndt {

/// A sweep's time and channel, for planning cycles.
struct SweepStamp {
  std::int64_t timestamp_us = 0;
  std::uint16_t channel = 0;
};

/// One cycle: `reference` and, per other channel that has one, its latest sweep within one period
/// before the reference sweep (t_ref − period < t ≤ t_ref). Indices into the planned list.
struct CyclePlan {
  std::size_t reference = 0;
  std::vector<std::size_t> members;  ///< includes `reference`, in channel order
};

/// Plans the cycles of a time-ordered sweep list. `period_us` ≤ 0: the median interval of the
/// reference channel's sweeps.
std::vector<CyclePlan> planRadarCycles(const std::vector<SweepStamp>& sweeps, std::uint16_t reference_channel,
                                       std::int64_t period_us = 0);

/// Where a radar sits on the vehicle (vehicle frame: x forward, y left), in 2D.
struct SensorMounting {
  double x = 0, y = 0, yaw = 0;
  bool valid = false;  ///< false for sensor ids no sweep of this cycle came from
};

/// The 2D mounting (x, y, yaw) of a sensor-to-vehicle calibration.
SensorMounting toMounting(const Eigen::Isometry3d& sensor_to_vehicle);

/// One radar's sweep as read: points in the sensor frame.
struct RadarSweepData {
  std::int64_t timestamp_us = 0;
  std::uint16_t sensor_id = 0;
  Eigen::Isometry3d sensor_to_vehicle = Eigen::Isometry3d::Identity();
  pcl::PointCloud<PointRadar> points;
};

struct RadarCycle {
  std::int64_t timestamp_us = 0;  ///< the reference sweep's time: the cycle's pose time
  std::vector<RadarSweepData> sweeps;
};

/// The channel that clocks the cycles: `asked` when given (an error naming the channels there are
/// when it is none of `mountings`), else the forward-facing radar (mounting yaw closest to 0; ties:
/// the one further forward). `mountings`: channel index → mounting of the channels with sweeps;
/// `names`: channel index → name; `where`: the scene or recording, for messages.
std::uint16_t chooseReferenceChannel(const std::map<std::uint16_t, SensorMounting>& mountings,
                                     const std::vector<std::string>& names, const std::string& asked,
                                     const std::string& where);

/// Radars that fell silent: per channel, one line for each gap of more than three of its own median
/// intervals between sweeps, naming the channel (`names`), its length and its times.
std::vector<std::string> findRadarSilences(const std::vector<SweepStamp>& stamps,
                                           const std::vector<std::string>& names);

/// Where the automotive pipeline gets its cycles: a nuScenes scene (nuscenes_sequence.h), a ROS bag
/// (radar_ndt/ros/rosbag_sequence.h), any recording planned into radar cycles. load() is called from
/// several threads at once and must not change the source.
class RadarCycleSource {
 public:
  virtual ~RadarCycleSource() = default;
  /// The scene's or recording's name, for results and messages.
  virtual const std::string& sceneName() const = 0;
  virtual const std::string& referenceChannel() const = 0;
  /// The mean interval between cycles (s); 0 with fewer than two.
  virtual double periodSeconds() const = 0;
  virtual std::size_t size() const = 0;
  /// Cycle k's time: its reference sweep's (µs).
  virtual std::int64_t timestamp(std::size_t k) const = 0;
  /// The vehicle's ground-truth poses at the cycles' times, SE(2) and relative to the first cycle;
  /// empty when the source has none.
  virtual Trajectory groundTruthTrajectory() const = 0;
  /// The ground truth as the source holds it, 6-DoF and stamped (s), in its own world frame: what
  /// the 6-DoF pipeline is judged against. By default the planar one above.
  virtual Trajectory groundTruth6Dof() const { return groundTruthTrajectory(); }
  /// Radars that fell silent (findRadarSilences).
  virtual const std::vector<std::string>& silences() const = 0;
  /// Reads cycle k's sweeps. A sweep that cannot be read is left out and described in `problems`;
  /// `non_finite_dropped` counts points dropped for NaN or Inf values.
  virtual RadarCycle load(std::size_t k, std::vector<std::string>* problems = nullptr,
                          std::size_t* non_finite_dropped = nullptr) const = 0;
};

}  // namespace radar_ndt

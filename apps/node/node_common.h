#pragma once
// What the ROS node's two pipelines share (docs/ros.md): their parameters from the run options'
// field table, the description's stamp rule, the counters and diagnostics of an input topic, the
// published odometry, TF and clouds, and the latency and CPU figures.

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <ros/ros.h>

#include "radar_ndt/io/live_vehicle_signals.h"
#include "radar_ndt/io/radar_point_fields.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/odometry/odometry_step.h"
#include "radar_ndt/odometry/radar_inertial_odometry.h"
#include "radar_ndt/pipeline/run_settings.h"
#include "radar_ndt/point_types.h"
#include "radar_ndt/ros/point_cloud2.h"

namespace radar_ndt {
namespace node {

/// The calling thread's CPU time (s).
double cpuSeconds();

/// The run's settings among the node's private parameters (node_parameters.h), each as its own
/// type; printed when there are any.
Settings nodeSettings(const ros::NodeHandle& pn);

/// A message's time by the description's rule: its header stamp, or its arrival when it has none.
std::int64_t stampOf(StampSource rule, const ros::Time& header);

/// An input topic's counters, for /diagnostics.
struct TopicState {
  TopicState() = default;
  TopicState(std::string topic_, std::string hardware_id_, std::string malformed_name_ = "malformed")
      : topic(std::move(topic_)), hardware_id(std::move(hardware_id_)), malformed_name(std::move(malformed_name_)) {}

  std::string topic, hardware_id;
  std::string malformed_name = "malformed";  ///< what the malformed messages are called in the status
  std::size_t messages = 0, malformed = 0, late = 0;
  std::int64_t last_us = -1;  ///< the newest message's time
  ros::WallTime last_arrival;
  std::string last_problem;

  /// A message at `t_us` arrived: counted; true when the stream went back in time by over half a
  /// second (a bag played again), `last_problem` then saying so.
  bool arrived(std::int64_t t_us);
  /// Whether a message has arrived and none for `seconds` since (the stream went quiet).
  bool quietFor(double seconds) const {
    return !last_arrival.isZero() && (ros::WallTime::now() - last_arrival).toSec() >= seconds;
  }
  /// `text` as the last problem, warned (at most once a second).
  void problem(const std::string& text);
  /// The topic's status: WARN when silent (no message for a second while `newest` arrived), or when
  /// messages were malformed or late; `extra` values after the counters.
  diagnostic_msgs::DiagnosticStatus status(const ros::WallTime& newest, const std::string& silent_text,
                                           const std::vector<std::pair<std::string, std::string>>& extra = {}) const;
};

/// A sample of one of the car's signals (`what`: "a yaw rate") at `t_us` into `signals`, as the
/// offline reader takes it; one that is not a number or older than what was already matched (the
/// node's `cycles`) is counted on `state` and said.
void takeSignal(LiveVehicleSignals& signals, LiveVehicleSignals::Signal signal, TopicState& state, std::int64_t t_us,
                double value, const std::string& what, const std::string& cycles);

/// A cloud's detections as `r`'s fields name them (sensor frame, sensor_id `id`), as the offline
/// reader converts them; nullopt when the cloud is malformed (counted and said on `state`).
/// Msg: sensor_msgs/PointCloud2, or sensor_msgs/PointCloud (NTU4DRadLM's Eagle).
template <typename Msg>
std::optional<pcl::PointCloud<PointRadar>> cloudPoints(const RadarDescription& r, std::uint16_t id, const Msg& msg,
                                                       TopicState& state) {
  try {
    const std::vector<std::string> names = r.fields.columns();
    const ros1::CloudColumns cols = ros1::readCloudColumns(msg, names);
    for (const std::string& need : r.fields.requiredColumns())
      for (std::size_t k = 0; k < names.size(); ++k)
        if (names[k] == need && !cols.present[k])
          throw std::invalid_argument("no field '" + need + "' (fields: " + ros1::fieldNames(msg) + ")");
    RadarPointStats stats;
    pcl::PointCloud<PointRadar> points =
        convertRadarPoints(cols.table, cols.points, cols.present, r.fields, id, &stats);
    if (stats.dropped_non_finite > 0)
      state.problem(r.topic + ": " + std::to_string(stats.dropped_non_finite) + " points with NaN or Inf dropped");
    if (cols.points == 0) state.problem(r.topic + ": an empty cloud");
    return points;
  } catch (const std::invalid_argument& e) {
    ++state.malformed;
    state.problem(r.topic + ": a malformed cloud left out: " + e.what());
    return std::nullopt;
  }
}

/// The latency (reference message received -> odometry published) and CPU of each cycle.
struct CycleTiming {
  std::vector<double> latency_s, cpu_s;
  /// The figures, printed at the end.
  void report(std::size_t cycles) const;
  double medianLatencyMs() const;
  /// The odometry's status: `count` and what they are ("cycles", "sweeps"), the median latency.
  diagnostic_msgs::DiagnosticStatus status(std::size_t count, const std::string& unit) const;
};

/// The node's publishers: ~odometry, ~local_map, ~map, /tf and /diagnostics.
class Publishers {
 public:
  Publishers(ros::NodeHandle& nh, ros::NodeHandle& pn);
  /// The step's pose as nav_msgs/Odometry (with the match's covariance) and TF odom -> base.
  void pose(const OdometryStep& step, std::int64_t t_us, const std::string& odom_frame, const std::string& base_frame);
  /// A 6-DoF step as nav_msgs/Odometry (its 6x6 covariance: position, then a small rotation about
  /// the odom frame's axes; the Doppler body velocity as the twist in the base frame) and TF.
  void pose(const OdometryStep3D& step, std::int64_t t_us, const std::string& odom_frame,
            const std::string& base_frame);
  bool wantsLocalMap() const { return local_map_.getNumSubscribers() > 0; }
  bool wantsMap() const { return map_.getNumSubscribers() > 0; }
  void localMap(const pcl::PointCloud<PointRadar>& cloud, std::int64_t t_us, const std::string& frame);
  void map(const pcl::PointCloud<PointRadar>& cloud, std::int64_t t_us, const std::string& frame);
  void diagnostics(std::vector<diagnostic_msgs::DiagnosticStatus> status);

 private:
  ros::Publisher odom_, local_map_, map_, tf_, diag_;
};

/// A running node; report() prints its figures when it stops.
class RadarNode {
 public:
  virtual ~RadarNode() = default;
  virtual void report() const = 0;
};

/// The automotive pipeline over the description's point-cloud radars (automotive_node.cpp).
std::unique_ptr<RadarNode> automotiveNode(ros::NodeHandle& nh, ros::NodeHandle& pn, const SensorDescription& d);
/// The scanning pipeline over the description's one scanning radar (scanning_node.cpp).
std::unique_ptr<RadarNode> scanningNode(ros::NodeHandle& nh, ros::NodeHandle& pn, const SensorDescription& d);
/// The 6-DoF pipeline over a 4D radar and the rig's IMU (inertial_node.cpp).
std::unique_ptr<RadarNode> inertialNode(ros::NodeHandle& nh, ros::NodeHandle& pn, const SensorDescription& d);

}  // namespace node
}  // namespace radar_ndt

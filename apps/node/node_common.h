#pragma once
// What the ROS node's two pipelines share (docs/ros.md): their parameters from the run options'
// field table, the description's stamp rule, the counters and diagnostics of an input topic, the
// published odometry, TF and clouds, and the latency and CPU figures.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <ros/ros.h>

#include "radar_ndt/io/live_vehicle_signals.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/odometry/odometry_step.h"
#include "radar_ndt/pipeline/run_settings.h"
#include "radar_ndt/point_types.h"

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

}  // namespace node
}  // namespace radar_ndt

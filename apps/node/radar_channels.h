#pragma once
// The description's point-cloud radars as a node receives them (docs/ros.md), shared by the
// automotive and the 6-DoF node: each radar's topic and counters, its mounting (the description's,
// else /tf_static and /tf through the MountingTree the offline reader uses: the description's frame,
// else the one its clouds name), and its sweeps assembled into cycles by the offline planner's rule
// (LiveCycles) once every radar is placed. Until then the sweeps wait, at most kMaxWaiting of them.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <diagnostic_msgs/DiagnosticStatus.h>
#include <ros/ros.h>
#include <tf2_msgs/TFMessage.h>
#include <topic_tools/shape_shifter.h>

#include "node/node_common.h"
#include "radar_ndt/io/live_cycles.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/ros/mounting_tree.h"

namespace radar_ndt {
namespace node {

class RadarChannels {
 public:
  /// Sweeps held at most while a radar waits for its mounting (a minute of a 16 Hz radar).
  static constexpr std::size_t kMaxWaiting = 1000;

  struct Channel {
    TopicState state;
    std::optional<Eigen::Isometry3d> mounting;
    std::string frame;     ///< the clouds' frame, for /tf when the description names none
    std::string unplaced;  ///< why the mounting is not known yet (the tree's answer)
  };

  /// What the node does at each turn.
  struct Handlers {
    /// A radar's stream went back in time (a bag played again): `from` says why; the node runs
    /// what it holds and starts again (reset() among it).
    std::function<void(TopicState& from, std::int64_t t_us)> restart;
    /// A cloud stamped `t_us` arrived (before it is read).
    std::function<void(std::int64_t t_us, ros::WallTime arrival)> stamped;
    /// Cycles may be complete: the node takes them with next().
    std::function<void()> ready;
    /// The oldest waiting sweep (at `t_us`) was dropped: a radar stays unplaced.
    std::function<void(std::int64_t t_us)> dropped;
  };

  /// `period_us`: LiveCycles' window (0: the running median of the reference's intervals).
  RadarChannels(const SensorDescription& d, std::int64_t period_us, Handlers handlers);

  /// Subscribes to every radar's topic (sensor_msgs/PointCloud2 or PointCloud, told by each
  /// message's type) and, while a radar is unplaced, to /tf and /tf_static.
  void subscribe(ros::NodeHandle& nh, std::vector<ros::Subscriber>& subs);

  /// The next complete cycle, its sweeps with their radars' mountings; none before every radar is
  /// placed.
  std::optional<RadarCycle> next();
  /// Every cycle still held, complete or not (the stream ended).
  std::vector<RadarCycle> flush();
  /// Forgets the sweeps held and the topics' last times (the stream starts again).
  void reset();

  /// The reference radar (LiveCycles' clock, chosen as the offline reader chooses it); none before
  /// every radar is placed.
  std::optional<std::uint16_t> reference() const {
    return live_ ? std::optional<std::uint16_t>(reference_) : std::nullopt;
  }
  std::size_t size() const { return channels_.size(); }
  const Channel& operator[](std::size_t i) const { return channels_[i]; }
  /// The newest cloud's arrival over every radar.
  ros::WallTime lastArrival() const;
  /// Radar i's mounting state for /diagnostics: known, waiting for what, or what the tree lacks.
  std::string mountingState(std::size_t i) const;
  /// Each radar's status (its `mounting` among the values), then /tf's when it had a problem.
  std::vector<diagnostic_msgs::DiagnosticStatus> status(const ros::WallTime& newest) const;
  /// The radars that sent nothing or were never placed, printed at the end.
  void report() const;

 private:
  bool allPlaced() const;
  void placeRadars();
  bool startCycles();
  void onTf(const tf2_msgs::TFMessage& m, const char* topic);
  void onAnyCloud(std::size_t i, const topic_tools::ShapeShifter& msg);
  template <typename Msg>
  void onCloud(std::size_t i, const Msg& msg);
  void take(RadarSweepData sweep);

  SensorDescription d_;
  std::int64_t period_us_ = 0;
  Handlers on_;
  std::vector<Channel> channels_;
  ros1::MountingTree tree_;  ///< /tf_static and /tf until every radar is placed
  TopicState tf_state_{"/tf", "tf"};
  std::uint16_t reference_ = 0;
  std::unique_ptr<LiveCycles> live_;     ///< null until every radar is placed
  std::vector<RadarSweepData> waiting_;  ///< sweeps before that, in arrival order
};

}  // namespace node
}  // namespace radar_ndt

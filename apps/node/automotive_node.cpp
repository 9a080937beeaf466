// The automotive radar odometry as a ROS node (docs/ros.md): subscribes to the radar topics of a
// sensor description, assembles cycles as they arrive (RadarChannels: the offline planner's
// rule), runs the front-end and the odometry the offline run uses. With ~odometry/car/gyro (the
// offline --imu) it fuses the description's IMU topic's yaw rate, with ~odometry/car/wheels (the
// offline --wheels) its speed topic's speed (geometry_msgs/TwistStamped or nav_msgs/Odometry), each
// cycle held until the signals have reached past it (LiveVehicleSignals).
#include <algorithm>
#include <cstdio>
#include <deque>
#include <map>
#include <optional>

#include <geometry_msgs/TwistStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/Imu.h>
#include <topic_tools/shape_shifter.h>

#include "node/node_common.h"
#include "node/radar_channels.h"
#include "radar_ndt/evaluation/point_map.h"
#include "radar_ndt/evaluation/run_report.h"
#include "radar_ndt/io/live_vehicle_signals.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/odometry_run.h"

namespace radar_ndt {
namespace node {
namespace {

class AutomotiveNode : public RadarNode {
 public:
  AutomotiveNode(ros::NodeHandle& nh, ros::NodeHandle& pn, const SensorDescription& d) : d_(d), pub_(nh, pn) {
    const Settings given = nodeSettings(pn);
    options_ = automotiveRunOptions(given);
    d_ = describedSensors(d_, options_, given);  // the radars the settings choose, as offline
    double period = 0;
    pn.param("cycle_period", period, 0.0);
    period_us_ = static_cast<std::int64_t>(period * 1e6 + 0.5);
    pn.param("flush_after", flush_after_, 0.5);
    pn.param<std::string>("odom_frame", odom_frame_, "odom");
    use_gyro_ = options_.odometry.car.gyro;
    use_speed_ = options_.odometry.car.wheels;
    if (use_gyro_ && d_.imu_topic.empty())
      throw std::invalid_argument("~odometry/car/gyro: " + d_.source + " names no imu topic");
    if (use_speed_ && d_.speed_topic.empty())
      throw std::invalid_argument("~odometry/car/wheels: " + d_.source + " names no speed topic");
    offset_us_ = std::llround(options_.odometry.car.time_offset * 1e6);
    std::vector<LiveVehicleSignals::Signal> in_use;
    if (use_gyro_) in_use.push_back(LiveVehicleSignals::Signal::YawRate);
    if (use_speed_) in_use.push_back(LiveVehicleSignals::Signal::Speed);
    car_ = LiveVehicleSignals(use_gyro_ ? d_.imu_topic : d_.speed_topic, in_use);
    imu_ = TopicState(d_.imu_topic, "imu", "not a number");
    speed_ = TopicState(d_.speed_topic, "speed", "not a speed");
    resetOdometry();
    RadarChannels::Handlers on;
    on.restart = [this](TopicState& from, std::int64_t t) { restart(from.last_problem, from, t); };
    on.stamped = [this](std::int64_t t, ros::WallTime arrival) {
      stream_us_ = std::max(stream_us_, t);
      arrival_.emplace(t, arrival);
    };
    on.ready = [this] { drain(); };
    radars_ = std::make_unique<RadarChannels>(d_, period_us_, std::move(on));
    radars_->subscribe(nh, subs_);
    if (use_gyro_)
      subs_.push_back(nh.subscribe<sensor_msgs::Imu>(d_.imu_topic, 2000, [this](const auto& m) { onImu(*m); }));
    if (use_speed_)  // either of two message types, told by each message's type
      subs_.push_back(
          nh.subscribe<topic_tools::ShapeShifter>(d_.speed_topic, 2000, [this](const auto& m) { onSpeed(*m); }));
    diag_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { diagnose(); });
    flush_timer_ = nh.createWallTimer(ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) { flushIfQuiet(); });
  }

  void report() const override {
    std::printf("%s", summaryText(stream_->result()).c_str());  // as radar_odometry prints a run's
    timing_.report(cycles_);
    radars_->report();
  }

 private:
  void resetOdometry() {
    stream_ = std::make_unique<AutomotiveStream>(options_, usesCar() ? car_.signals() : nullptr, "radar_ndt_node");
  }

  /// The stream went back in time (a bag played again) on `from`, at `t`: the old stream's cycles
  /// still held are run, as at its end offline, and everything starts again.
  void restart(const std::string& why, TopicState& from, std::int64_t t) {
    ROS_WARN_STREAM("radar_ndt_node: " << why << ": the odometry starts again");
    finishStream();  // empties pending_
    radars_->reset();
    imu_.last_us = speed_.last_us = -1;
    stream_us_ = -1;
    car_.reset();
    resetOdometry();
    map_ = PointMap(0.2);
    from.last_us = t;
  }

  bool usesCar() const { return use_gyro_ || use_speed_; }

  /// A sample of one of the car's signals on `state`'s topic, taken as the offline reader takes it.
  void onSignal(LiveVehicleSignals::Signal signal, TopicState& state, const ros::Time& header, double value,
                const char* what) {
    const std::int64_t t = stampOf(d_.stamps, header);
    if (state.arrived(t)) restart(state.last_problem, state, t);
    stream_us_ = std::max(stream_us_, t - offset_us_);
    takeSignal(car_, signal, state, t, value, what, "cycles");
    processReady();
  }

  void onImu(const sensor_msgs::Imu& msg) {
    onSignal(LiveVehicleSignals::Signal::YawRate, imu_, msg.header.stamp,
             imuYawRate(d_, Eigen::Vector3d(msg.angular_velocity.x, msg.angular_velocity.y, msg.angular_velocity.z)),
             "a yaw rate");
  }

  /// The speed: twist.linear.x of a geometry_msgs/TwistStamped or nav_msgs/Odometry (as offline).
  void onSpeed(const topic_tools::ShapeShifter& msg) {
    const std::string& type = msg.getDataType();
    if (type == "geometry_msgs/TwistStamped") {
      const auto m = msg.instantiate<geometry_msgs::TwistStamped>();
      onSignal(LiveVehicleSignals::Signal::Speed, speed_, m->header.stamp, m->twist.linear.x, "a speed");
    } else if (type == "nav_msgs/Odometry") {
      const auto m = msg.instantiate<nav_msgs::Odometry>();
      onSignal(LiveVehicleSignals::Signal::Speed, speed_, m->header.stamp, m->twist.twist.linear.x, "a speed");
    } else {
      ++speed_.messages;
      ++speed_.malformed;
      speed_.problem(speed_.topic + ": a " + type +
                     ": the speed is read from geometry_msgs/TwistStamped or nav_msgs/Odometry: left out");
    }
  }

  void drain() {
    while (auto cycle = radars_->next()) pending_.push_back(std::move(*cycle));
    processReady();
  }

  /// The complete cycles, oldest first, each once the car's signals have reached past it (when they
  /// are fused).
  void processReady() {
    while (!pending_.empty() &&
           (!usesCar() || car_.reaches(pending_.front().timestamp_us + offset_us_, stream_us_ + offset_us_))) {
      process(pending_.front());
      pending_.pop_front();
    }
  }

  void flushIfQuiet() {
    const ros::WallTime last = radars_->lastArrival();
    if (last.isZero() || (ros::WallTime::now() - last).toSec() < flush_after_) return;
    finishStream();
  }

  /// The stream ended (quiet, or played again): every cycle still held is run, complete or not and
  /// whether or not the car's signals reached it, as the offline run ends at the bag's end.
  void finishStream() {
    for (RadarCycle& cycle : radars_->flush()) pending_.push_back(std::move(cycle));
    for (RadarCycle& cycle : pending_) process(cycle);
    pending_.clear();
  }

  /// One cycle through the offline run's step (AutomotiveStream), published.
  void process(RadarCycle& cycle) {
    const double cpu0 = cpuSeconds();
    const std::int64_t t = cycle.timestamp_us;
    const AutomotiveStream::Added a = stream_->add(std::move(cycle));
    for (const std::string& p : a.problems) ROS_WARN_STREAM_THROTTLE(1.0, "radar_ndt_node: " << p);
    const OdometryStep& step = a.step;
    if (usesCar()) car_.used(t + offset_us_);
    map_.add(*a.cloud, step.pose);
    pub_.pose(step, t, odom_frame_, d_.base_frame);
    if (pub_.wantsLocalMap()) pub_.localMap(*stream_->odometry().localMap().cloud(), t, d_.base_frame);
    if (pub_.wantsMap() && cycles_ % 10 == 0) pub_.map(map_.cloud(), t, odom_frame_);
    ++cycles_;
    timing_.cpu_s.push_back(cpuSeconds() - cpu0);
    const auto arrived = arrival_.find(t);
    if (arrived != arrival_.end()) {
      timing_.latency_s.push_back((ros::WallTime::now() - arrived->second).toSec());
      arrival_.erase(arrival_.begin(), std::next(arrived));
    }
  }

  void diagnose() {
    const ros::WallTime newest = radars_->lastArrival();
    std::vector<diagnostic_msgs::DiagnosticStatus> status = radars_->status(newest);
    if (use_gyro_)
      status.push_back(imu_.status(
          newest, "silent: no IMU message for over a second while the radars send; the last yaw rate is held"));
    if (use_speed_)
      status.push_back(speed_.status(
          newest, "silent: no speed message for over a second while the radars send; the last speed is held"));
    status.push_back(timing_.status(cycles_, "cycles"));
    pub_.diagnostics(std::move(status));
  }

  SensorDescription d_;
  Publishers pub_;
  AutomotiveRunOptions options_;
  std::int64_t period_us_ = 0;
  double flush_after_ = 0.5;
  std::string odom_frame_;
  std::unique_ptr<AutomotiveStream> stream_;  ///< the offline run's step, a cycle at a time
  std::unique_ptr<RadarChannels> radars_;     ///< the radars' topics, mountings and cycles
  TopicState imu_;    ///< the IMU topic's counters (its mounting unused: only the yaw rate is fused)
  TopicState speed_;  ///< the speed topic's
  bool use_gyro_ = false, use_speed_ = false;
  std::int64_t offset_us_ = 0;  ///< the car's clock minus the radars' (odometry.car.time_offset)
  LiveVehicleSignals car_;
  std::int64_t stream_us_ = -1;     ///< the newest message time seen, on the radars' clock
  std::deque<RadarCycle> pending_;  ///< complete cycles waiting for the car's signals
  std::map<std::int64_t, ros::WallTime> arrival_;
  CycleTiming timing_;
  std::size_t cycles_ = 0;
  std::vector<ros::Subscriber> subs_;
  PointMap map_{0.2};  ///< every cycle's stationary detections in the odom frame, as --map-out
  ros::WallTimer diag_timer_, flush_timer_;
};

}  // namespace

std::unique_ptr<RadarNode> automotiveNode(ros::NodeHandle& nh, ros::NodeHandle& pn, const SensorDescription& d) {
  return std::make_unique<AutomotiveNode>(nh, pn, d);
}

}  // namespace node
}  // namespace radar_ndt

// A 4D radar rig's 6-DoF odometry as a ROS node (docs/ros.md): the description's radars (each
// placed by its mounting in the description, else from /tf_static and /tf as the offline reader
// takes it from the bag: RadarChannels), their sweeps planned into cycles and grouped by time as
// the offline run groups them, and, with ~imu (the offline --imu), the rig's IMU (sensor_msgs/Imu,
// turned into the base frame by imu_mounting), run through the offline 6-DoF run's step
// (InertialStream) in its order: each step held until an IMU message later than its measurement
// time has arrived, every IMU message up to that time handed over first. Publishes ~odometry
// (nav_msgs/Odometry with z, the full rotation and the 6x6 covariance), TF odom -> base_link,
// ~local_map (the keyframes the next scan is matched against, in base_link) and /diagnostics.
#include <algorithm>
#include <cstdio>
#include <deque>
#include <map>

#include <sensor_msgs/Imu.h>

#include "node/node_common.h"
#include "node/radar_channels.h"
#include "radar_ndt/odometry/local_map_3d.h"
#include "radar_ndt/pipeline/inertial_run.h"

namespace radar_ndt {
namespace node {
namespace {

class InertialNode : public RadarNode {
 public:
  InertialNode(ros::NodeHandle& nh, ros::NodeHandle& pn, const SensorDescription& d) : d_(d), pub_(nh, pn) {
    if (d_.radars.empty()) throw std::invalid_argument("~sensors: " + d_.source + " describes no radar");
    given_ = nodeSettings(pn);
    options_ = inertialRunOptions(given_, inertialRunDefaults(d_, d_.radars.front().name));  // said now if bad
    if (options_.matcher.method == "doppler-imu")
      throw std::invalid_argument("~matcher/method doppler-imu smooths a whole recording: radar_odometry runs it");
    if (options_.imu && d_.imu_topic.empty()) throw std::invalid_argument("~imu: " + d_.source + " names no imu topic");
    double period = 0;
    pn.param("cycle_period", period, 0.0);
    pn.param("flush_after", flush_after_, 0.5);
    pn.param<std::string>("odom_frame", odom_frame_, "odom");
    imu_state_ = TopicState(d_.imu_topic, "imu", "not finite");
    restartOdometry();
    RadarChannels::Handlers on;
    on.restart = [this](TopicState& from, std::int64_t t) { restart(from, t); };
    on.stamped = [this](std::int64_t t, ros::WallTime arrival) { arrival_.emplace(t, arrival); };
    on.ready = [this] { drain(); };
    on.dropped = [this](std::int64_t t_us) {  // a radar never placed: the IMU before its dropped sweep goes too
      const double t = static_cast<double>(t_us) * 1e-6 - options_.radar_latency;
      while (!imu_.empty() && imu_.front().t <= t) imu_.pop_front();
    };
    radars_ = std::make_unique<RadarChannels>(d_, static_cast<std::int64_t>(period * 1e6 + 0.5), std::move(on));
    radars_->subscribe(nh, subs_);
    if (options_.imu)
      subs_.push_back(nh.subscribe<sensor_msgs::Imu>(d_.imu_topic, 4000, [this](const auto& m) { onImu(*m); }));
    diag_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { diagnose(); });
    flush_timer_ = nh.createWallTimer(ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) { flushIfQuiet(); });
  }

  void report() const override {
    std::printf("radar_ndt_node: %zu scans, %zu poses, %zu matched, %zu fallbacks, %zu still\n", scans_, cycles_,
                matched_, fallbacks_, still_);
    for (const std::string& p : stream_->odometry().problems()) std::printf("radar_ndt_node: %s\n", p.c_str());
    timing_.report(cycles_);
    radars_->report();
  }

 private:
  /// A new stream (no mounting of its own: each step's sweeps carry theirs, InertialStream::addScans).
  void restartOdometry() {
    stream_ = std::make_unique<InertialStream>(options_, Eigen::Isometry3d::Identity());
    imu_.clear();
    newest_imu_ = -1;
  }

  /// The stream went back in time (a bag played again) on `from`: what is held is run, as at the
  /// end offline, and everything starts again.
  void restart(TopicState& from, std::int64_t t) {
    ROS_WARN_STREAM("radar_ndt_node: " << from.last_problem << ": the odometry starts again");
    finish();
    radars_->reset();
    imu_state_.last_us = -1;
    restartOdometry();
    from.last_us = t;
  }

  /// An IMU message at its stamp (the description's rule), in the base frame's axes, as the offline
  /// reader takes it; a non-finite one is counted and left out, as offline.
  void onImu(const sensor_msgs::Imu& msg) {
    const std::int64_t t = stampOf(d_.stamps, msg.header.stamp);
    if (imu_state_.arrived(t)) restart(imu_state_, t);
    const Eigen::Matrix3d R = imuRotation(d_);
    ImuSample s;
    s.t = 1e-6 * static_cast<double>(t);
    s.gyro = R * Eigen::Vector3d(msg.angular_velocity.x, msg.angular_velocity.y, msg.angular_velocity.z);
    s.accel = R * Eigen::Vector3d(msg.linear_acceleration.x, msg.linear_acceleration.y, msg.linear_acceleration.z);
    if (!s.gyro.allFinite() || !s.accel.allFinite()) {
      ++imu_state_.malformed;
      imu_state_.problem(d_.imu_topic + ": a reading not finite: left out");
      return;
    }
    imu_.push_back(s);
    newest_imu_ = std::max(newest_imu_, s.t);
    processReady(false);
  }

  /// A cycle's sweeps as steps, grouped by time as the offline run groups them.
  void enqueue(RadarCycle& cycle) {
    for (std::vector<RadarSweepData>& group : sweepsByTime(std::move(cycle.sweeps), options_.merge_sweeps))
      pending_.push_back(std::move(group));
  }

  void drain() {
    // The run's defaults are the reference radar's (its accuracy), as offline; chosen once every
    // radar is placed, before the first step.
    if (!configured_ && radars_->reference()) {
      options_ = inertialRunOptions(given_, inertialRunDefaults(d_, d_.radars[*radars_->reference()].name));
      stream_ = std::make_unique<InertialStream>(options_, Eigen::Isometry3d::Identity());
      configured_ = true;
    }
    while (auto cycle = radars_->next()) enqueue(*cycle);
    processReady(false);
  }

  /// The steps, oldest first, each once an IMU message later than its measurement time has
  /// arrived (when the IMU is fused); `all` runs every one (the stream went quiet).
  void processReady(bool all) {
    while (!pending_.empty()) {
      // The step's measurement time as the offline run computes it.
      const double tm = static_cast<double>(pending_.front().back().timestamp_us) * 1e-6 - options_.radar_latency;
      if (!all && options_.imu && newest_imu_ <= tm) break;
      while (!imu_.empty() && imu_.front().t <= tm) {  // as offline: every message up to the scan first
        stream_->addImu(imu_.front());
        imu_.pop_front();
      }
      process(pending_.front());
      pending_.pop_front();
    }
  }

  /// Every cycle still held, complete or not, and every step, as at the end offline.
  void finish() {
    for (RadarCycle& cycle : radars_->flush()) enqueue(cycle);
    processReady(true);
  }

  void flushIfQuiet() {
    const ros::WallTime last = radars_->lastArrival();
    if (!last.isZero() && (ros::WallTime::now() - last).toSec() >= flush_after_) finish();
  }

  void process(const std::vector<RadarSweepData>& group) {
    const double cpu0 = cpuSeconds();
    const std::int64_t t_us = group.back().timestamp_us;  // a merged group's latest
    const OdometryStep3D step = stream_->addScans(static_cast<double>(t_us) * 1e-6, group);
    ++scans_;
    if (!step.why.empty() && step.fallback) ROS_WARN_STREAM_THROTTLE(1.0, "radar_ndt_node: " << step.why);
    if (!step.skipped) {
      const std::int64_t t = std::llround(step.stamp * 1e6);
      pub_.pose(step, t, odom_frame_, d_.base_frame);
      if (pub_.wantsLocalMap()) publishLocalMap(step, t);
      ++cycles_;
      matched_ += step.matched;
      fallbacks_ += step.fallback;
      still_ += step.still;
    }
    timing_.cpu_s.push_back(cpuSeconds() - cpu0);
    const auto arrived = arrival_.find(t_us);
    if (arrived != arrival_.end()) {
      timing_.latency_s.push_back((ros::WallTime::now() - arrived->second).toSec());
      arrival_.erase(arrival_.begin(), std::next(arrived));
    }
  }

  /// The local map the next scan is matched against, in the base frame of this one.
  void publishLocalMap(const OdometryStep3D& step, std::int64_t t) {
    const LocalMap3D& map = stream_->odometry().map();
    if (map.empty()) return;
    const pcl::PointCloud<PointRadar4D> local = transformRadar4D(*map.cloud(), step.pose.inverse());
    pcl::PointCloud<PointRadar> out;
    out.reserve(local.size());
    for (const PointRadar4D& p : local) {
      PointRadar q;
      q.x = p.x, q.y = p.y, q.z = p.z, q.power = p.power, q.doppler = p.doppler;
      out.push_back(q);
    }
    pub_.localMap(out, t, d_.base_frame);
  }

  void diagnose() {
    const ros::WallTime newest = std::max(radars_->lastArrival(), imu_state_.last_arrival);
    std::vector<diagnostic_msgs::DiagnosticStatus> status = radars_->status(newest);
    if (options_.imu)
      status.push_back(imu_state_.status(
          newest, "silent: no IMU message for over a second while the radars send; their scans wait for it"));
    status.push_back(timing_.status(cycles_, "scans"));
    pub_.diagnostics(std::move(status));
  }

  SensorDescription d_;
  Publishers pub_;
  Settings given_;  ///< the node's parameters as the run's settings
  InertialRunOptions options_;
  bool configured_ = false;  ///< options_ from the reference radar's description, once it is chosen
  double flush_after_ = 0.5;
  std::string odom_frame_;
  std::unique_ptr<RadarChannels> radars_;  ///< the radars' topics, mountings and cycles
  std::unique_ptr<InertialStream> stream_;
  TopicState imu_state_;
  std::deque<ImuSample> imu_;                        ///< IMU messages not yet handed over, in arrival order
  std::deque<std::vector<RadarSweepData>> pending_;  ///< steps (sweeps of one time) waiting for the IMU
  double newest_imu_ = -1;                           ///< s: the newest IMU message's time
  std::map<std::int64_t, ros::WallTime> arrival_;    ///< each cloud's arrival, by its stamp
  std::size_t scans_ = 0, cycles_ = 0, matched_ = 0, fallbacks_ = 0, still_ = 0;
  CycleTiming timing_;
  std::vector<ros::Subscriber> subs_;
  ros::WallTimer diag_timer_, flush_timer_;
};

}  // namespace

std::unique_ptr<RadarNode> inertialNode(ros::NodeHandle& nh, ros::NodeHandle& pn, const SensorDescription& d) {
  return std::make_unique<InertialNode>(nh, pn, d);
}

}  // namespace node
}  // namespace radar_ndt

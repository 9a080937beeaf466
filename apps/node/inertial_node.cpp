// A 4D radar's 6-DoF odometry as a ROS node (docs/ros.md): the description's reference radar (its
// mounting from the description, else from /tf_static and /tf as the offline reader takes it from
// the bag: the description's frame, else the one its clouds name) and, with ~imu (the offline --imu), the rig's IMU
// (sensor_msgs/Imu, turned into the base frame by imu_mounting), run through the offline 6-DoF
// run's step (InertialStream) in its order: each scan held until an IMU message later than its
// measurement time has arrived, every IMU message up to that time handed over first. Publishes
// ~odometry (nav_msgs/Odometry with z, the full rotation and the 6x6 covariance), TF odom ->
// base_link, ~local_map (the keyframes the next scan is matched against, in base_link) and
// /diagnostics.
#include <algorithm>
#include <cstdio>
#include <deque>

#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>
#include <topic_tools/shape_shifter.h>

#include "node/node_common.h"
#include "radar_ndt/odometry/local_map_3d.h"
#include "radar_ndt/pipeline/inertial_run.h"
#include "radar_ndt/ros/mounting_tree.h"

namespace radar_ndt {
namespace node {
namespace {

/// A scan received and waiting for the IMU.
/// Scans held at most while the radar waits for its mounting (a minute at 16 Hz).
constexpr std::size_t kMaxUnplacedScans = 1000;

struct Scan {
  std::int64_t t_us = 0;
  pcl::PointCloud<PointRadar> points;
  ros::WallTime arrival;
};

/// The radar the 6-DoF node runs: the description's reference, else its first.
const RadarDescription& runningRadar(const SensorDescription& d) {
  for (const RadarDescription& r : d.radars)
    if (r.name == d.reference) return r;
  if (d.radars.empty()) throw std::invalid_argument("~sensors: " + d.source + " describes no radar");
  return d.radars.front();
}

class InertialNode : public RadarNode {
 public:
  InertialNode(ros::NodeHandle& nh, ros::NodeHandle& pn, const SensorDescription& d)
      : d_(d), radar_(runningRadar(d)), pub_(nh, pn) {
    if (radar_.mounting) mounting_ = radar_.mounting->transform();
    if (d_.radars.size() > 1)
      ROS_WARN_STREAM("radar_ndt_node: the 6-DoF node runs one radar, " << radar_.name << "; " << d_.radars.size() - 1
                                                                        << " left out");
    options_ = inertialRunOptions(nodeSettings(pn), inertialRunDefaults(d_, radar_.name));
    if (options_.matcher.method == "doppler-imu")
      throw std::invalid_argument("~matcher/method doppler-imu smooths a whole recording: radar_odometry runs it");
    if (options_.imu && d_.imu_topic.empty()) throw std::invalid_argument("~imu: " + d_.source + " names no imu topic");
    pn.param("flush_after", flush_after_, 0.5);
    pn.param<std::string>("odom_frame", odom_frame_, "odom");
    radar_state_ = TopicState(radar_.topic, radar_.name);
    imu_state_ = TopicState(d_.imu_topic, "imu", "not finite");
    restartOdometry();
    subs_.push_back(nh.subscribe<topic_tools::ShapeShifter>(
        radar_.topic, 200, [this](const topic_tools::ShapeShifter::ConstPtr& m) { onAnyCloud(*m); }));
    if (options_.imu)
      subs_.push_back(nh.subscribe<sensor_msgs::Imu>(d_.imu_topic, 4000, [this](const auto& m) { onImu(*m); }));
    if (!mounting_) {  // whenever it arrives: a latched /tf_static reaches the node at its subscription
      subs_.push_back(nh.subscribe<tf2_msgs::TFMessage>("/tf", 200, [this](const auto& m) { onTf(*m, "/tf"); }));
      subs_.push_back(
          nh.subscribe<tf2_msgs::TFMessage>("/tf_static", 20, [this](const auto& m) { onTf(*m, "/tf_static"); }));
    }
    diag_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { diagnose(); });
    flush_timer_ = nh.createWallTimer(ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) { flushIfQuiet(); });
  }

  void report() const override {
    std::printf("radar_ndt_node: %zu scans, %zu poses, %zu matched, %zu fallbacks, %zu still\n", scans_, cycles_,
                matched_, fallbacks_, still_);
    if (stream_)
      for (const std::string& p : stream_->odometry().problems()) std::printf("radar_ndt_node: %s\n", p.c_str());
    timing_.report(cycles_);
    if (!mounting_ && radar_state_.messages > 0)
      std::printf("radar_ndt_node: radar %s was never placed: %s; its %zu scans were not run\n", radar_.name.c_str(),
                  mountingState().c_str(), pending_.size());
  }

 private:
  /// A new stream once the radar is placed; until then the scans wait (the IMU messages with them).
  void restartOdometry() {
    stream_.reset();
    if (mounting_) stream_ = std::make_unique<InertialStream>(options_, *mounting_);
    imu_.clear();
    newest_imu_ = -1;
  }

  /// A /tf or /tf_static message: its transforms join the tree until the radar is placed.
  void onTf(const tf2_msgs::TFMessage& m, const char* topic) {
    if (mounting_) return;
    std::vector<std::string> bad;
    tree_.add(m, topic, &bad);
    for (const std::string& b : bad) tf_state_.problem(b);
    place();
  }

  /// The radar's mounting from the tree once its frame is known (the description's, else its
  /// clouds'), as the offline reader takes it; the scans held so far then run.
  void place() {
    const std::string& frame = radar_.frame.empty() ? cloud_frame_ : radar_.frame;
    if (mounting_ || frame.empty()) return;
    mounting_ = tree_.lookup(d_.base_frame, frame, &unplaced_);
    if (!mounting_) return;
    stream_ = std::make_unique<InertialStream>(options_, *mounting_);
    processReady(false);
  }

  /// Not placed for long: the oldest scan waiting is dropped (said), and the IMU messages before it,
  /// so that a radar never placed does not hold the whole recording.
  void dropOldestUnplaced() {
    const double t = static_cast<double>(pending_.front().t_us) * 1e-6 - options_.radar_latency;
    pending_.pop_front();
    while (!imu_.empty() && imu_.front().t <= t) imu_.pop_front();
    radar_state_.problem("radar " + radar_.name + " not placed (" + mountingState() +
                         "): its oldest waiting scan dropped");
  }

  std::string mountingState() const {
    if (mounting_) return "known";
    if (radar_.frame.empty() && cloud_frame_.empty()) return "waiting for a cloud to name its frame";
    return unplaced_.empty() ? "waiting for /tf_static or /tf" : unplaced_;
  }

  /// The stream went back in time (a bag played again) on `from`: the scans held are run, as at
  /// the end offline, and everything starts again.
  void restart(TopicState& from, std::int64_t t) {
    ROS_WARN_STREAM("radar_ndt_node: " << from.last_problem << ": the odometry starts again");
    processReady(true);
    radar_state_.last_us = imu_state_.last_us = -1;
    last_scan_us_ = -1;
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

  void onAnyCloud(const topic_tools::ShapeShifter& msg) {
    const std::string& type = msg.getDataType();
    if (type == "sensor_msgs/PointCloud2") return onCloud(*msg.instantiate<sensor_msgs::PointCloud2>());
    if (type == "sensor_msgs/PointCloud") return onCloud(*msg.instantiate<sensor_msgs::PointCloud>());
    ++radar_state_.malformed;
    radar_state_.problem(radar_.topic + ": a " + type +
                         ": radar clouds are read from sensor_msgs/PointCloud2 or sensor_msgs/PointCloud: left out");
  }

  template <typename Msg>
  void onCloud(const Msg& msg) {
    const ros::WallTime arrival = ros::WallTime::now();
    if (cloud_frame_.empty() && !msg.header.frame_id.empty()) {
      cloud_frame_ = msg.header.frame_id;
      place();
    }
    const std::int64_t t = stampOf(d_.stamps, msg.header.stamp);
    if (radar_state_.arrived(t)) restart(radar_state_, t);
    if (last_scan_us_ >= 0 && t <= last_scan_us_) {  // offline, the scans are in stamp order
      ++radar_state_.late;
      radar_state_.problem(radar_.topic + ": a scan not later than the last: left out");
      return;
    }
    std::optional<pcl::PointCloud<PointRadar>> points = cloudPoints(radar_, 0, msg, radar_state_);
    if (!points) return;
    last_scan_us_ = t;
    pending_.push_back(Scan{t, std::move(*points), arrival});
    if (!stream_ && pending_.size() > kMaxUnplacedScans) dropOldestUnplaced();
    processReady(false);
  }

  /// The scans, oldest first, each once an IMU message later than its measurement time has
  /// arrived (when the IMU is fused); `all` runs every one (the stream went quiet).
  void processReady(bool all) {
    if (!stream_) return;  // the radar is not placed yet
    while (!pending_.empty()) {
      // The scan's measurement time as the offline run computes it.
      const double tm = static_cast<double>(pending_.front().t_us) * 1e-6 - options_.radar_latency;
      if (!all && options_.imu && newest_imu_ <= tm) break;
      while (!imu_.empty() && imu_.front().t <= tm) {  // as offline: every message up to the scan first
        stream_->addImu(imu_.front());
        imu_.pop_front();
      }
      process(pending_.front());
      pending_.pop_front();
    }
  }

  void flushIfQuiet() {
    if (!pending_.empty() && radar_state_.quietFor(flush_after_)) processReady(true);
  }

  void process(const Scan& s) {
    const double cpu0 = cpuSeconds();
    const OdometryStep3D step = stream_->addScan(static_cast<double>(s.t_us) * 1e-6, s.points);
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
    timing_.latency_s.push_back((ros::WallTime::now() - s.arrival).toSec());
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
    const ros::WallTime newest = std::max(radar_state_.last_arrival, imu_state_.last_arrival);
    std::vector<diagnostic_msgs::DiagnosticStatus> status;
    status.push_back(radar_state_.status(newest, "silent: no scan for over a second while the IMU sends",
                                         {{"mounting", mountingState()}}));
    if (!tf_state_.last_problem.empty()) status.push_back(tf_state_.status(ros::WallTime(), ""));
    if (options_.imu)
      status.push_back(imu_state_.status(
          newest, "silent: no IMU message for over a second while the radar sends; its scans wait for it"));
    status.push_back(timing_.status(cycles_, "scans"));
    pub_.diagnostics(std::move(status));
  }

  SensorDescription d_;
  RadarDescription radar_;
  Publishers pub_;
  InertialRunOptions options_;
  double flush_after_ = 0.5;
  std::string odom_frame_;
  std::optional<Eigen::Isometry3d> mounting_;  ///< radar -> base: the description's, else the tree's
  std::string cloud_frame_;                    ///< the clouds' frame, for /tf when the description names none
  std::string unplaced_;                       ///< why the tree does not place the radar yet
  ros1::MountingTree tree_;                    ///< /tf_static and /tf until the radar is placed
  TopicState tf_state_{"/tf", "tf"};
  std::unique_ptr<InertialStream> stream_;  ///< null until the radar is placed
  TopicState radar_state_, imu_state_;
  std::deque<ImuSample> imu_;  ///< IMU messages not yet handed over, in arrival order
  std::deque<Scan> pending_;   ///< scans waiting for the IMU to pass them
  double newest_imu_ = -1;     ///< s: the newest IMU message's time
  std::int64_t last_scan_us_ = -1;
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

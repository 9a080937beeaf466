// A scanning radar's odometry as a ROS node (docs/ros.md): subscribes to the description's polar
// images (sensor_msgs/Image, laid out as its `polar` key says: ros1::polarScanFromImage, as the
// bag reader decodes them) and runs each sweep, in stamp order, through the threshold and
// odometry of the offline scanning run (ScanningStream). With ~odometry/gyro/enabled (the offline
// --imu) it takes the description's IMU topic's yaw rate, each sweep held until the gyro has
// reached past it (LiveVehicleSignals).
#include <algorithm>
#include <deque>

#include <pcl/common/transforms.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>

#include "node/node_common.h"
#include "radar_ndt/evaluation/point_map.h"
#include "radar_ndt/io/live_vehicle_signals.h"
#include "radar_ndt/pipeline/scanning_run.h"
#include "radar_ndt/ros/rosbag_scans.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {
namespace node {
namespace {

/// A sweep received and waiting to be run.
struct Sweep {
  sensor_msgs::Image::ConstPtr image;
  std::int64_t t_us = 0;
  ros::WallTime arrival;
};

class ScanningNode : public RadarNode {
 public:
  ScanningNode(ros::NodeHandle& nh, ros::NodeHandle& pn, const SensorDescription& d)
      : d_(d), radar_(d.radars.at(0)), pub_(nh, pn) {
    if (d_.radars.size() != 1)
      throw std::invalid_argument("~sensors: " + d_.source + ": a scanning radar is described alone");
    options_ = scanningRunOptions(nodeSettings(pn), "rosbag");
    double period = 0;
    pn.param("cycle_period", period, 0.0);
    // The azimuths' times are spread over the sweep period: the described one, else this
    // parameter, else (as offline) the median interval between the sweeps received so far.
    sweep_us_ = std::llround(1e6 * (radar_.polar.sweep_period > 0 ? radar_.polar.sweep_period : period));
    pn.param("flush_after", flush_after_, 0.5);
    pn.param<std::string>("odom_frame", odom_frame_, "odom");
    use_gyro_ = options_.odometry.gyro.enabled;
    if (use_gyro_ && d_.imu_topic.empty())
      throw std::invalid_argument("~odometry/gyro/enabled: " + d_.source + " names no imu topic");
    offset_us_ = std::llround(options_.odometry.gyro.time_offset * 1e6);
    yaw_ = LiveVehicleSignals(d_.imu_topic);
    radar_state_ = TopicState(radar_.topic, radar_.name);
    imu_ = TopicState(d_.imu_topic, "imu", "not a number");
    restartOdometry();
    subs_.push_back(nh.subscribe<sensor_msgs::Image>(radar_.topic, 100, [this](const auto& m) { onImage(m); }));
    if (use_gyro_)
      subs_.push_back(nh.subscribe<sensor_msgs::Imu>(d_.imu_topic, 2000, [this](const auto& m) { onImu(*m); }));
    diag_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { diagnose(); });
    flush_timer_ = nh.createWallTimer(ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) { flushIfQuiet(); });
  }

  void report() const override { timing_.report(cycles_); }

 private:
  void restartOdometry() {
    stream_ = std::make_unique<ScanningStream>(options_);
    if (use_gyro_) {
      const std::shared_ptr<const VehicleSignals> s = yaw_.signals();
      stream_->setYawRate(std::shared_ptr<const TimeSeries>(s, &s->yaw_rate));
    }
    map_ = PointMap(0.2);
    keyframe_pose_ = Pose2::Zero();
  }

  /// The stream went back in time (a bag played again) on `from`, at `t`: the old stream's sweeps
  /// still held are run, as at its end offline, and everything starts again.
  void restart(TopicState& from, std::int64_t t) {
    ROS_WARN_STREAM("radar_ndt_node: " << from.last_problem << ": the odometry starts again");
    processReady(true);
    last_taken_us_ = -1;
    intervals_.clear();
    median_interval_us_ = 0;
    radar_state_.last_us = imu_.last_us = -1;
    stream_us_ = -1;
    yaw_.reset();
    restartOdometry();
    from.last_us = t;
  }

  void onImu(const sensor_msgs::Imu& msg) {
    const std::int64_t t = stampOf(d_.stamps, msg.header.stamp);
    if (imu_.arrived(t)) restart(imu_, t);
    stream_us_ = std::max(stream_us_, t - offset_us_);
    takeSignal(yaw_, LiveVehicleSignals::Signal::YawRate, imu_, t,
               imuYawRate(d_, Eigen::Vector3d(msg.angular_velocity.x, msg.angular_velocity.y, msg.angular_velocity.z)),
               "a yaw rate", "sweeps");
    processReady(false);
  }

  void onImage(const sensor_msgs::Image::ConstPtr& m) {
    const ros::WallTime arrival = ros::WallTime::now();
    const std::int64_t t = stampOf(d_.stamps, m->header.stamp);
    if (radar_state_.arrived(t)) restart(radar_state_, t);
    stream_us_ = std::max(stream_us_, t);
    const std::string at = radar_.topic + " at " + std::to_string(t) + " us";
    if (last_taken_us_ >= 0 && t <= last_taken_us_) {
      // Offline, the sweeps are sorted and a repeated stamp's second message left out.
      ++radar_state_.late;
      radar_state_.problem(at + (t == last_taken_us_ ? ": a second sweep at this stamp: left out"
                                                     : ": older than the last sweep: left out"));
      return;
    }
    try {
      ros1::checkPolarImage(m->encoding, m->height, m->width, m->step, m->data.size());
    } catch (const std::invalid_argument& e) {
      ++radar_state_.malformed;
      radar_state_.problem(at + ": " + e.what() + ": left out");
      return;
    }
    taken(t);
    pending_.push_back(Sweep{m, t, arrival});
    processReady(false);
  }

  /// The sweep period the azimuths' times are spread over; 0 while unknown.
  std::int64_t sweepPeriod() const { return sweep_us_ > 0 ? sweep_us_ : median_interval_us_; }

  /// A sweep at `t_us` taken: the median interval of the sweeps so far (the offline run takes the
  /// whole bag's).
  void taken(std::int64_t t_us) {
    if (last_taken_us_ >= 0) intervals_.push_back(t_us - last_taken_us_);
    last_taken_us_ = t_us;
    if (sweep_us_ > 0 || intervals_.empty()) return;
    std::vector<std::int64_t> v = intervals_;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    median_interval_us_ = v[v.size() / 2];
  }

  /// The sweeps, oldest first, each once its period is known and the gyro has reached past it (when
  /// it is fused); `all` runs every one (the stream went quiet).
  void processReady(bool all) {
    while (!pending_.empty()) {
      const Sweep& s = pending_.front();
      const bool ready =
          all || (sweepPeriod() > 0 && (!use_gyro_ || yaw_.reaches(s.t_us + offset_us_, stream_us_ + offset_us_)));
      if (!ready) break;
      process(s);
      pending_.pop_front();
    }
  }

  void flushIfQuiet() {
    if (!pending_.empty() && radar_state_.quietFor(flush_after_)) processReady(true);
  }

  void process(const Sweep& s) {
    const double cpu0 = cpuSeconds();
    const sensor_msgs::Image& m = *s.image;
    const std::string name = radar_.topic + " at " + std::to_string(s.t_us) + " us";
    PolarScan scan =
        ros1::polarScanFromImage(m.encoding, m.height, m.width, m.step, m.data, s.t_us, sweepPeriod(), radar_.polar);
    ScanningStream::Added a = stream_->add(std::move(scan), name, true);
    if (use_gyro_) yaw_.used(s.t_us + offset_us_);
    if (!a.problem.empty()) radar_state_.problem(a.problem);
    if (a.published) {
      const OdometryStep& step = a.step;
      // As --map-out: the keyframe scans' points (and the first scan's).
      if (step.keyframe || cycles_ == 0) {
        if (!a.bridged) map_.add(a.points, step.pose);
        keyframe_pose_ = step.pose;
      }
      pub_.pose(step, s.t_us, odom_frame_, d_.base_frame);
      if (pub_.wantsLocalMap()) publishKeyframe(step, s.t_us);
      if (pub_.wantsMap() && cycles_ % 10 == 0) pub_.map(map_.cloud(), s.t_us, odom_frame_);
      ++cycles_;
    }
    timing_.cpu_s.push_back(cpuSeconds() - cpu0);
    timing_.latency_s.push_back((ros::WallTime::now() - s.arrival).toSec());
  }

  /// The keyframe the next sweep is matched against, in the base frame of this one.
  void publishKeyframe(const OdometryStep& step, std::int64_t t_us) {
    const pcl::PointCloud<PointRadar>::ConstPtr keyframe = stream_->odometry().keyframeCloud();
    if (!keyframe) return;
    pcl::PointCloud<PointRadar> local;
    pcl::transformPointCloud(*keyframe, local, toMatrix4(between(step.pose, keyframe_pose_)));
    pub_.localMap(local, t_us, d_.base_frame);
  }

  void diagnose() {
    const ros::WallTime newest = std::max(radar_state_.last_arrival, imu_.last_arrival);
    std::vector<diagnostic_msgs::DiagnosticStatus> status;
    status.push_back(radar_state_.status(newest, "silent: no sweep for over a second while the IMU sends",
                                         {{"sweep_period_ms", std::to_string(1e-3 * sweepPeriod())}}));
    if (use_gyro_)
      status.push_back(imu_.status(
          newest, "silent: no IMU message for over a second while the radar sends; the last yaw rate is held"));
    status.push_back(timing_.status(cycles_, "sweeps"));
    pub_.diagnostics(std::move(status));
  }

  SensorDescription d_;
  RadarDescription radar_;
  Publishers pub_;
  ScanningRunOptions options_;
  std::int64_t sweep_us_ = 0;  ///< the sweep period when described or given; 0: from the stamps
  double flush_after_ = 0.5;
  std::string odom_frame_;
  std::unique_ptr<ScanningStream> stream_;
  TopicState radar_state_, imu_;
  bool use_gyro_ = false;
  std::int64_t offset_us_ = 0;           ///< the gyro's clock minus the radar's (odometry.gyro.time_offset)
  LiveVehicleSignals yaw_;               ///< the gyro's yaw rate alone
  std::int64_t stream_us_ = -1;          ///< the newest message time seen, on the radar's clock
  std::int64_t last_taken_us_ = -1;      ///< the last sweep taken
  std::vector<std::int64_t> intervals_;  ///< between the sweeps taken since the start
  std::int64_t median_interval_us_ = 0;
  std::deque<Sweep> pending_;  ///< sweeps waiting for their period or the gyro
  Pose2 keyframe_pose_ = Pose2::Zero();
  CycleTiming timing_;
  std::size_t cycles_ = 0;
  std::vector<ros::Subscriber> subs_;
  PointMap map_{0.2};  ///< the keyframe scans' points in the odom frame, as --map-out
  ros::WallTimer diag_timer_, flush_timer_;
};

}  // namespace

std::unique_ptr<RadarNode> scanningNode(ros::NodeHandle& nh, ros::NodeHandle& pn, const SensorDescription& d) {
  return std::make_unique<ScanningNode>(nh, pn, d);
}

}  // namespace node
}  // namespace radar_ndt

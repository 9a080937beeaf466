// radar_ndt_node: the automotive radar odometry as a ROS 1 node (docs/ros.md). Subscribes to the
// radar topics of a sensor description, assembles cycles as they arrive (ros1::LiveCycles, the
// offline planner's rule), runs the front-end and the odometry the offline run uses, and publishes
// ~odometry (nav_msgs/Odometry with the match's covariance), the TF odom -> base_link (REP 105),
// ~local_map (sensor_msgs/PointCloud2, the local map in base_link), ~map (the stationary
// detections in odom, as --map-out writes them, latched, every tenth cycle) and /diagnostics. With
// ~odometry/car/gyro (the offline --imu) it fuses the description's IMU topic's yaw rate, each cycle
// held until the gyro has reached past it (ros1::LiveYawRate). Its parameters are the run options'
// field table: ~odometry/submap_size, ~matcher/method, ... (one source with the command line and
// Python).
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <deque>
#include <map>
#include <memory>
#include <optional>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include "field_options.h"
#include "radar_ndt/evaluation/point_map.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/ros/live_cycles.h"
#include "radar_ndt/ros/live_yaw_rate.h"
#include "radar_ndt/ros/point_cloud2.h"
#include "radar_ndt/ros/ros_time.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;
using ros1::microseconds;
using ros1::rosTime;

namespace {

double cpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_THREAD, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5))];
}

/// The run options from the private parameters, one for each field of the table (a field's path
/// with '/' for '.'), given as text, numbers or booleans.
AutomotiveRunOptions optionsFromParameters(const ros::NodeHandle& pn) {
  AutomotiveRunOptions o;
  for (const auto& f : apps::fieldOptions(o, true)) {
    std::string name = f.path;
    std::replace(name.begin(), name.end(), '.', '/');
    XmlRpc::XmlRpcValue v;
    if (!pn.getParam(name, v)) continue;
    std::string text;
    switch (v.getType()) {
      case XmlRpc::XmlRpcValue::TypeBoolean: text = static_cast<bool>(v) ? "true" : "false"; break;
      case XmlRpc::XmlRpcValue::TypeInt: text = std::to_string(static_cast<int>(v)); break;
      case XmlRpc::XmlRpcValue::TypeDouble: text = std::to_string(static_cast<double>(v)); break;
      case XmlRpc::XmlRpcValue::TypeString: text = static_cast<std::string>(v); break;
      default: throw std::invalid_argument("~" + name + ": expected a number, a boolean or text");
    }
    if (f.off_switch) {
      if (text == "true") f.set(o, text);
    } else {
      f.set(o, text);
    }
  }
  o = withMethod(o, o.matcher.method);
  o.validate();
  return o;
}

class Node {
 public:
  Node(ros::NodeHandle& nh, ros::NodeHandle& pn) : pn_(pn) {
    std::string sensors;
    if (!pn.getParam("sensors", sensors)) throw std::invalid_argument("~sensors: the sensor description is required");
    d_ = readSensorDescription(sensors);
    for (const RadarDescription& r : d_.radars)
      if (r.kind == RadarKind::Scanning)
        throw std::invalid_argument("~sensors: radar " + r.name +
                                    " is a scanning radar: the node runs the automotive pipeline (a scanning "
                                    "radar's bag: radar_odometry --format rosbag)");
    options_ = optionsFromParameters(pn);
    double period = 0;
    pn.param("cycle_period", period, 0.0);
    period_us_ = static_cast<std::int64_t>(period * 1e6 + 0.5);
    pn.param("flush_after", flush_after_, 0.5);
    pn.param<std::string>("odom_frame", odom_frame_, "odom");
    front_end_ = std::make_unique<AutomotiveFrontEnd>(options_.front_end);
    if (options_.odometry.car.wheels)
      throw std::invalid_argument(
          "~odometry/car/wheels: the node reads no wheel speeds (docs/ros.md); "
          "~odometry/car/gyro fuses the IMU's yaw rate");
    use_gyro_ = options_.odometry.car.gyro;
    if (use_gyro_ && d_.imu_topic.empty())
      throw std::invalid_argument("~odometry/car/gyro: " + d_.source + " names no imu topic");
    offset_us_ = std::llround(options_.odometry.car.time_offset * 1e6);
    yaw_ = ros1::LiveYawRate(d_.imu_topic);
    resetOdometry();
    for (std::size_t i = 0; i < d_.radars.size(); ++i) {
      const RadarDescription& r = d_.radars[i];
      channel_state_.emplace_back();
      if (r.mounting) channel_state_.back().mounting = r.mounting->transform();
      subs_.push_back(nh.subscribe<sensor_msgs::PointCloud2>(
          r.topic, 200, [this, i](const sensor_msgs::PointCloud2::ConstPtr& m) { onCloud(i, *m); }));
    }
    if (use_gyro_)
      subs_.push_back(nh.subscribe<sensor_msgs::Imu>(d_.imu_topic, 2000, [this](const auto& m) { onImu(*m); }));
    subs_.push_back(nh.subscribe<tf2_msgs::TFMessage>("/tf", 200, [this](const auto& m) { onTf(*m); }));
    subs_.push_back(nh.subscribe<tf2_msgs::TFMessage>("/tf_static", 20, [this](const auto& m) { onTf(*m); }));
    odom_pub_ = pn.advertise<nav_msgs::Odometry>("odometry", 100);
    map_pub_ = pn.advertise<sensor_msgs::PointCloud2>("local_map", 5);
    world_pub_ = pn.advertise<sensor_msgs::PointCloud2>("map", 1, true);
    tf_pub_ = nh.advertise<tf2_msgs::TFMessage>("/tf", 100);
    diag_pub_ = nh.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
    diag_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { diagnose(); });
    flush_timer_ = nh.createWallTimer(ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) { flushIfQuiet(); });
  }

  /// The latency and CPU figures, printed at the end.
  void report() const {
    std::printf(
        "radar_ndt_node: %zu cycles; latency (reference sweep received -> odometry published) median %.3f ms, "
        "p99 %.3f ms; CPU per cycle median %.3f ms\n",
        cycles_, 1e3 * percentile(latency_s_, 0.5), 1e3 * percentile(latency_s_, 0.99), 1e3 * percentile(cpu_s_, 0.5));
    std::fflush(stdout);
  }

 private:
  struct ChannelState {
    std::optional<Eigen::Isometry3d> mounting;
    std::string frame;
    std::size_t messages = 0, malformed = 0, late = 0;
    std::int64_t last_us = -1;
    ros::WallTime last_arrival;
    std::string last_problem;
  };

  void resetOdometry() {
    odometry_ = std::make_unique<AutomotiveOdometry>(options_.odometry, makeMatcher(options_.matcher));
    if (use_gyro_) odometry_->setVehicleSignals(yaw_.signals());
    have_valid_ = false;
  }

  /// A message's time by the description's rule: its header stamp, or its arrival when it has none.
  std::int64_t stampOf(const ros::Time& header) const {
    const bool use_header = d_.stamps == StampSource::Header || (d_.stamps == StampSource::Auto && !header.isZero());
    return microseconds(use_header ? header : ros::Time::now());
  }

  /// The stream went back in time (a bag played again): everything starts again.
  void restart(const std::string& why) {
    ROS_WARN_STREAM("radar_ndt_node: " << why << ": the odometry starts again");
    live_.reset();
    waiting_.clear();
    pending_.clear();
    for (auto& s : channel_state_) s.last_us = -1;
    imu_.last_us = -1;
    stream_us_ = -1;
    yaw_.reset();
    resetOdometry();
    map_ = PointMap(0.2);
  }

  void onImu(const sensor_msgs::Imu& msg) {
    const std::int64_t t = stampOf(msg.header.stamp);
    ++imu_.messages;
    imu_.last_arrival = ros::WallTime::now();
    if (imu_.last_us >= 0 && t < imu_.last_us - 500000) {
      imu_.last_problem = d_.imu_topic + ": time jumped back";
      restart(imu_.last_problem);
    }
    imu_.last_us = t;
    stream_us_ = std::max(stream_us_, t - offset_us_);
    const auto added = yaw_.add(t, msg.angular_velocity.z);
    if (added == ros1::LiveYawRate::Added::NotFinite || added == ros1::LiveYawRate::Added::Late) {
      const bool nan = added == ros1::LiveYawRate::Added::NotFinite;
      ++(nan ? imu_.malformed : imu_.late);
      imu_.last_problem = d_.imu_topic + (nan ? ": a yaw rate that is not a number: left out"
                                              : ": a message older than the cycles already matched: left out");
      ROS_WARN_STREAM_THROTTLE(1.0, "radar_ndt_node: " << imu_.last_problem);
    }
    processReady();
  }

  void problem(std::size_t i, const std::string& text) {
    channel_state_[i].last_problem = text;
    ROS_WARN_STREAM_THROTTLE(1.0, "radar_ndt_node: " << text);
  }

  std::optional<std::uint16_t> reference() {
    if (live_) return reference_;
    std::map<std::uint16_t, SensorMounting> m;
    std::vector<std::string> names;
    for (std::size_t i = 0; i < d_.radars.size(); ++i) {
      names.push_back(d_.radars[i].name);
      if (!channel_state_[i].mounting) return std::nullopt;  // decided once every radar is placed
      m[static_cast<std::uint16_t>(i)] = toMounting(*channel_state_[i].mounting);
    }
    reference_ = chooseReferenceChannel(m, names, d_.reference, "the node's radars");
    live_ = std::make_unique<ros1::LiveCycles>(reference_, period_us_);
    for (auto& s : waiting_) live_->add(std::move(s));
    waiting_.clear();
    return reference_;
  }

  void onTf(const tf2_msgs::TFMessage& m) {
    for (const auto& t : m.transforms)
      for (std::size_t i = 0; i < d_.radars.size(); ++i) {
        ChannelState& c = channel_state_[i];
        const std::string frame = d_.radars[i].frame.empty() ? c.frame : d_.radars[i].frame;
        if (c.mounting || frame.empty() || t.header.frame_id != d_.base_frame || t.child_frame_id != frame) continue;
        Eigen::Quaterniond q(t.transform.rotation.w, t.transform.rotation.x, t.transform.rotation.y,
                             t.transform.rotation.z);
        if (!(std::abs(q.norm() - 1.0) < 1e-2)) continue;
        q.normalize();
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = q.toRotationMatrix();
        T.translation() << t.transform.translation.x, t.transform.translation.y, t.transform.translation.z;
        c.mounting = T;
      }
    drain();
  }

  void onCloud(std::size_t i, const sensor_msgs::PointCloud2& msg) {
    const ros::WallTime arrival = ros::WallTime::now();
    ChannelState& c = channel_state_[i];
    const RadarDescription& r = d_.radars[i];
    ++c.messages;
    c.last_arrival = arrival;
    if (c.frame.empty()) c.frame = msg.header.frame_id;
    const std::int64_t t = stampOf(msg.header.stamp);
    if (c.last_us >= 0 && t < c.last_us - 500000) {  // the stream went back in time: a bag played again
      c.last_problem = r.topic + ": time jumped back by " + std::to_string((c.last_us - t) / 1000) + " ms";
      restart(c.last_problem);
    }
    c.last_us = t;
    stream_us_ = std::max(stream_us_, t);
    RadarSweepData sweep;
    sweep.timestamp_us = t;
    sweep.sensor_id = static_cast<std::uint16_t>(i);
    try {
      const std::vector<std::string> names = r.fields.columns();
      const ros1::CloudColumns cols = ros1::readCloudColumns(msg, names);
      for (const std::string& need : r.fields.requiredColumns())
        for (std::size_t k = 0; k < names.size(); ++k)
          if (names[k] == need && !cols.present[k])
            throw std::invalid_argument("no field '" + need + "' (fields: " + ros1::fieldNames(msg) + ")");
      RadarPointStats stats;
      sweep.points = convertRadarPoints(cols.table, cols.points, cols.present, r.fields, sweep.sensor_id, &stats);
      if (stats.dropped_non_finite > 0)
        problem(i, r.topic + ": " + std::to_string(stats.dropped_non_finite) + " points with NaN or Inf dropped");
      if (cols.points == 0) problem(i, r.topic + ": an empty cloud");
    } catch (const std::invalid_argument& e) {
      ++c.malformed;
      problem(i, r.topic + ": a malformed cloud left out: " + e.what());
      return;
    }
    arrival_.emplace(t, arrival);
    if (!reference()) {
      waiting_.push_back(std::move(sweep));
      return;
    }
    const auto added = live_->add(std::move(sweep));
    if (added == ros1::LiveCycles::Added::Late) {
      ++c.late;
      problem(i, r.topic + ": a sweep older than the last cycle arrived late: left out");
    }
    drain();
  }

  void drain() {
    if (!reference()) return;
    while (auto cycle = live_->next()) pending_.push_back(std::move(*cycle));
    processReady();
  }

  /// The complete cycles, oldest first, each once the gyro has reached past it (when it is fused).
  void processReady() {
    while (!pending_.empty() &&
           (!use_gyro_ || yaw_.reaches(pending_.front().timestamp_us + offset_us_, stream_us_ + offset_us_))) {
      process(pending_.front());
      pending_.pop_front();
    }
  }

  void flushIfQuiet() {
    if (!live_) return;
    ros::WallTime last;
    for (const auto& c : channel_state_) last = std::max(last, c.last_arrival);
    if (last.isZero() || (ros::WallTime::now() - last).toSec() < flush_after_) return;
    for (RadarCycle& cycle : live_->flush()) pending_.push_back(std::move(cycle));
    for (RadarCycle& cycle : pending_) process(cycle);
    pending_.clear();
  }

  void process(RadarCycle& cycle) {
    const double cpu0 = cpuSeconds();
    for (RadarSweepData& s : cycle.sweeps) s.sensor_to_vehicle = *channel_state_[s.sensor_id].mounting;
    ProcessedCycle processed = front_end_->process(cycle);
    if (!processed.ego.valid && have_valid_) processed = front_end_->process(cycle, &last_valid_);
    if (processed.ego.valid) {
      last_valid_ = processed.ego;
      have_valid_ = true;
    }
    const OdometryStep& step = odometry_->add(processed);
    if (use_gyro_) yaw_.used(cycle.timestamp_us + offset_us_);
    map_.add(*processed.cloud, step.pose);
    publish(step, cycle.timestamp_us);
    ++cycles_;
    cpu_s_.push_back(cpuSeconds() - cpu0);
    const auto a = arrival_.find(cycle.timestamp_us);
    if (a != arrival_.end()) {
      latency_s_.push_back((ros::WallTime::now() - a->second).toSec());
      arrival_.erase(arrival_.begin(), std::next(a));
    }
  }

  void publish(const OdometryStep& step, std::int64_t t_us) {
    const ros::Time stamp = rosTime(t_us);
    const Eigen::Isometry3d pose = toIsometry3(step.pose);
    const Eigen::Quaterniond q(pose.linear());
    nav_msgs::Odometry o;
    o.header.stamp = stamp;
    o.header.frame_id = odom_frame_;
    o.child_frame_id = d_.base_frame;
    o.pose.pose.position.x = pose.translation().x();
    o.pose.pose.position.y = pose.translation().y();
    o.pose.pose.orientation.w = q.w();
    o.pose.pose.orientation.x = q.x();
    o.pose.pose.orientation.y = q.y();
    o.pose.pose.orientation.z = q.z();
    // The match's covariance (x, y, yaw of the step) where there is one; unknown (-1) otherwise (REP 145).
    const Eigen::Matrix3d& C = step.match_covariance;
    const int idx[3] = {0, 1, 5};
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k)
        o.pose.covariance[static_cast<std::size_t>(6 * idx[r] + idx[k])] = C.allFinite() ? C(r, k) : -1.0;
    odom_pub_.publish(o);
    tf2_msgs::TFMessage tf;
    geometry_msgs::TransformStamped t;
    t.header = o.header;
    t.child_frame_id = d_.base_frame;
    t.transform.translation.x = pose.translation().x();
    t.transform.translation.y = pose.translation().y();
    t.transform.rotation = o.pose.pose.orientation;
    tf.transforms.push_back(t);
    tf_pub_.publish(tf);
    if (map_pub_.getNumSubscribers() > 0) publishCloud(map_pub_, *odometry_->localMap().cloud(), stamp, d_.base_frame);
    if (world_pub_.getNumSubscribers() > 0 && cycles_ % 10 == 0)
      publishCloud(world_pub_, map_.cloud(), stamp, odom_frame_);
  }

  static void publishCloud(ros::Publisher& pub, const pcl::PointCloud<PointRadar>& cloud_in, const ros::Time& stamp,
                           const std::string& frame) {
    const pcl::PointCloud<PointRadar>* cloud = &cloud_in;
    sensor_msgs::PointCloud2 m;
    m.header.stamp = stamp;
    m.header.frame_id = frame;
    const char* names[] = {"x", "y", "z", "doppler"};
    for (std::uint32_t k = 0; k < 4; ++k) {
      sensor_msgs::PointField f;
      f.name = names[k];
      f.offset = 4 * k;
      f.datatype = sensor_msgs::PointField::FLOAT32;
      f.count = 1;
      m.fields.push_back(f);
    }
    m.height = 1;
    m.width = static_cast<std::uint32_t>(cloud->size());
    m.point_step = 16;
    m.row_step = 16 * m.width;
    m.is_dense = true;
    m.data.resize(m.row_step);
    for (std::size_t i = 0; i < cloud->size(); ++i) {
      const float v[4] = {(*cloud)[i].x, (*cloud)[i].y, (*cloud)[i].z, (*cloud)[i].doppler};
      std::memcpy(&m.data[16 * i], v, sizeof v);
    }
    pub.publish(m);
  }

  void diagnose() {
    diagnostic_msgs::DiagnosticArray a;
    a.header.stamp = ros::Time::now();
    const ros::WallTime now = ros::WallTime::now();
    ros::WallTime newest;
    for (const auto& c : channel_state_) newest = std::max(newest, c.last_arrival);
    for (std::size_t i = 0; i < d_.radars.size(); ++i) {
      const ChannelState& c = channel_state_[i];
      diagnostic_msgs::DiagnosticStatus s;
      s.name = "radar_ndt: " + d_.radars[i].topic;
      s.hardware_id = d_.radars[i].name;
      const bool silent = !newest.isZero() && (c.last_arrival.isZero() || (newest - c.last_arrival).toSec() > 1.0);
      s.level = silent || c.malformed > 0 || c.late > 0 ? diagnostic_msgs::DiagnosticStatus::WARN
                                                        : diagnostic_msgs::DiagnosticStatus::OK;
      s.message = silent ? "silent: no cloud for over a second while the other radars send"
                         : (c.last_problem.empty() ? "OK" : c.last_problem);
      auto kv = [&](const std::string& k, const std::string& v) {
        diagnostic_msgs::KeyValue x;
        x.key = k;
        x.value = v;
        s.values.push_back(x);
      };
      kv("messages", std::to_string(c.messages));
      kv("malformed", std::to_string(c.malformed));
      kv("late", std::to_string(c.late));
      kv("mounting", c.mounting ? "known" : "waiting for /tf");
      a.status.push_back(s);
    }
    if (use_gyro_) {
      diagnostic_msgs::DiagnosticStatus g;
      g.name = "radar_ndt: " + d_.imu_topic;
      g.hardware_id = "imu";
      const bool silent =
          !newest.isZero() && (imu_.last_arrival.isZero() || (newest - imu_.last_arrival).toSec() > 1.0);
      g.level = silent || imu_.malformed > 0 || imu_.late > 0 ? diagnostic_msgs::DiagnosticStatus::WARN
                                                              : diagnostic_msgs::DiagnosticStatus::OK;
      g.message = silent ? "silent: no IMU message for over a second while the radars send; the last yaw rate is held"
                         : (imu_.last_problem.empty() ? "OK" : imu_.last_problem);
      for (const auto& [k, v] : {std::pair<std::string, std::size_t>{"messages", imu_.messages},
                                 {"not a number", imu_.malformed},
                                 {"late", imu_.late}}) {
        diagnostic_msgs::KeyValue x;
        x.key = k;
        x.value = std::to_string(v);
        g.values.push_back(x);
      }
      a.status.push_back(g);
    }
    diagnostic_msgs::DiagnosticStatus s;
    s.name = "radar_ndt: odometry";
    s.level = diagnostic_msgs::DiagnosticStatus::OK;
    s.message = std::to_string(cycles_) + " cycles";
    diagnostic_msgs::KeyValue lat;
    lat.key = "latency_median_ms";
    lat.value = std::to_string(1e3 * percentile(latency_s_, 0.5));
    s.values.push_back(lat);
    a.status.push_back(s);
    (void)now;
    diag_pub_.publish(a);
  }

  ros::NodeHandle pn_;
  SensorDescription d_;
  AutomotiveRunOptions options_;
  std::int64_t period_us_ = 0;
  double flush_after_ = 0.5;
  std::string odom_frame_;
  std::unique_ptr<AutomotiveFrontEnd> front_end_;
  std::unique_ptr<AutomotiveOdometry> odometry_;
  EgoVelocity last_valid_;
  bool have_valid_ = false;
  std::vector<ChannelState> channel_state_;
  ChannelState imu_;  ///< the IMU topic's counters (its mounting unused: only the yaw rate is fused)
  bool use_gyro_ = false;
  std::int64_t offset_us_ = 0;  ///< the gyro's clock minus the radars' (odometry.car.time_offset)
  ros1::LiveYawRate yaw_;
  std::int64_t stream_us_ = -1;     ///< the newest message time seen, on the radars' clock
  std::deque<RadarCycle> pending_;  ///< complete cycles waiting for the gyro
  std::uint16_t reference_ = 0;
  std::unique_ptr<ros1::LiveCycles> live_;
  std::vector<RadarSweepData> waiting_;
  std::map<std::int64_t, ros::WallTime> arrival_;
  std::vector<double> latency_s_, cpu_s_;
  std::size_t cycles_ = 0;
  std::vector<ros::Subscriber> subs_;
  ros::Publisher odom_pub_, map_pub_, world_pub_, tf_pub_, diag_pub_;
  PointMap map_{0.2};  ///< every cycle's stationary detections in the odom frame, as --map-out
  ros::WallTimer diag_timer_, flush_timer_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "radar_ndt");
  ros::NodeHandle nh, pn("~");
  try {
    Node node(nh, pn);
    ros::spin();
    node.report();
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("radar_ndt_node: " << e.what());
    return 1;
  }
  return 0;
}

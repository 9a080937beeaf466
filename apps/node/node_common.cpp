#include "node/node_common.h"

#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>
#include <stdexcept>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include "node/node_parameters.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/scanning_run.h"
#include "radar_ndt/ros/point_cloud2.h"
#include "radar_ndt/ros/ros_time.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {
namespace node {

using ros1::microseconds;
using ros1::rosTime;

double cpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_THREAD, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

namespace {

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5))];
}

void publishCloud(ros::Publisher& pub, const pcl::PointCloud<PointRadar>& cloud, std::int64_t t_us,
                  const std::string& frame) {
  using F = sensor_msgs::PointField;
  sensor_msgs::PointCloud2 m =
      ros1::writeCloud({"x", "y", "z", "doppler"}, {F::FLOAT32, F::FLOAT32, F::FLOAT32, F::FLOAT32}, cloud.size(),
                       [&cloud](std::size_t i, std::size_t k) {
                         const PointRadar& p = cloud[i];
                         return static_cast<double>(k == 0 ? p.x : k == 1 ? p.y : k == 2 ? p.z : p.doppler);
                       });
  m.header.stamp = rosTime(t_us);
  m.header.frame_id = frame;
  m.is_dense = true;  // every point's position is finite
  pub.publish(m);
}

}  // namespace

Settings nodeSettings(const ros::NodeHandle& pn) {
  const std::string prefix = pn.getNamespace() + "/";
  std::vector<std::string> names;
  pn.getParamNames(names);
  std::map<std::string, XmlRpc::XmlRpcValue> params;
  for (const std::string& name : names) {
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    XmlRpc::XmlRpcValue v;
    if (pn.getParam(name, v)) params[name.substr(prefix.size())] = v;
  }
  Settings given = settingsFromParameters(params);
  if (!given.empty()) ROS_INFO_STREAM("radar_ndt_node: settings: " << settingsText(given));
  return given;
}

std::int64_t stampOf(StampSource rule, const ros::Time& header) {
  const bool use_header = rule == StampSource::Header || (rule == StampSource::Auto && !header.isZero());
  return microseconds(use_header ? header : ros::Time::now());
}

bool TopicState::arrived(std::int64_t t_us) {
  ++messages;
  last_arrival = ros::WallTime::now();
  const bool back = last_us >= 0 && t_us < last_us - 500000;
  if (back) last_problem = topic + ": time jumped back by " + std::to_string((last_us - t_us) / 1000) + " ms";
  last_us = t_us;
  return back;
}

void TopicState::problem(const std::string& text) {
  last_problem = text;
  ROS_WARN_STREAM_THROTTLE(1.0, "radar_ndt_node: " << text);
}

diagnostic_msgs::DiagnosticStatus TopicState::status(
    const ros::WallTime& newest, const std::string& silent_text,
    const std::vector<std::pair<std::string, std::string>>& extra) const {
  diagnostic_msgs::DiagnosticStatus s;
  s.name = "radar_ndt: " + topic;
  s.hardware_id = hardware_id;
  const bool silent = !newest.isZero() && (last_arrival.isZero() || (newest - last_arrival).toSec() > 1.0);
  s.level = silent || malformed > 0 || late > 0 ? diagnostic_msgs::DiagnosticStatus::WARN
                                                : diagnostic_msgs::DiagnosticStatus::OK;
  s.message = silent ? silent_text : (last_problem.empty() ? "OK" : last_problem);
  auto kv = [&s](const std::string& k, const std::string& v) {
    diagnostic_msgs::KeyValue x;
    x.key = k;
    x.value = v;
    s.values.push_back(x);
  };
  kv("messages", std::to_string(messages));
  kv(malformed_name, std::to_string(malformed));
  kv("late", std::to_string(late));
  for (const auto& [k, v] : extra) kv(k, v);
  return s;
}

void CycleTiming::report(std::size_t cycles) const {
  std::printf(
      "radar_ndt_node: %zu cycles; latency (reference sweep received -> odometry published) median %.3f ms, "
      "p99 %.3f ms; CPU per cycle median %.3f ms\n",
      cycles, 1e3 * percentile(latency_s, 0.5), 1e3 * percentile(latency_s, 0.99), 1e3 * percentile(cpu_s, 0.5));
  std::fflush(stdout);
}

double CycleTiming::medianLatencyMs() const {
  return 1e3 * percentile(latency_s, 0.5);
}

diagnostic_msgs::DiagnosticStatus CycleTiming::status(std::size_t count, const std::string& unit) const {
  diagnostic_msgs::DiagnosticStatus s;
  s.name = "radar_ndt: odometry";
  s.level = diagnostic_msgs::DiagnosticStatus::OK;
  s.message = std::to_string(count) + " " + unit;
  diagnostic_msgs::KeyValue lat;
  lat.key = "latency_median_ms";
  lat.value = std::to_string(medianLatencyMs());
  s.values.push_back(lat);
  return s;
}

void takeSignal(LiveVehicleSignals& signals, LiveVehicleSignals::Signal signal, TopicState& state, std::int64_t t_us,
                double value, const std::string& what, const std::string& cycles) {
  const auto added = signals.add(signal, t_us, value);
  if (added != LiveVehicleSignals::Added::NotFinite && added != LiveVehicleSignals::Added::Late) return;
  const bool nan = added == LiveVehicleSignals::Added::NotFinite;
  ++(nan ? state.malformed : state.late);
  state.problem(state.topic + (nan ? ": " + what + " that is not a number: left out"
                                   : ": a message older than the " + cycles + " already matched: left out"));
}

Publishers::Publishers(ros::NodeHandle& nh, ros::NodeHandle& pn)
    : odom_(pn.advertise<nav_msgs::Odometry>("odometry", 100)),
      local_map_(pn.advertise<sensor_msgs::PointCloud2>("local_map", 5)),
      map_(pn.advertise<sensor_msgs::PointCloud2>("map", 1, true)),
      tf_(nh.advertise<tf2_msgs::TFMessage>("/tf", 100)),
      diag_(nh.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10)) {}

void Publishers::pose(const OdometryStep& step, std::int64_t t_us, const std::string& odom_frame,
                      const std::string& base_frame) {
  const Eigen::Isometry3d pose = toIsometry3(step.pose);
  const Eigen::Quaterniond q(pose.linear());
  nav_msgs::Odometry o;
  o.header.stamp = rosTime(t_us);
  o.header.frame_id = odom_frame;
  o.child_frame_id = base_frame;
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
  odom_.publish(o);
  tf2_msgs::TFMessage tf;
  geometry_msgs::TransformStamped t;
  t.header = o.header;
  t.child_frame_id = base_frame;
  t.transform.translation.x = pose.translation().x();
  t.transform.translation.y = pose.translation().y();
  t.transform.rotation = o.pose.pose.orientation;
  tf.transforms.push_back(t);
  tf_.publish(tf);
}

void Publishers::pose(const OdometryStep3D& step, std::int64_t t_us, const std::string& odom_frame,
                      const std::string& base_frame) {
  const Eigen::Quaterniond q(step.pose.linear());
  nav_msgs::Odometry o;
  o.header.stamp = rosTime(t_us);
  o.header.frame_id = odom_frame;
  o.child_frame_id = base_frame;
  o.pose.pose.position.x = step.pose.translation().x();
  o.pose.pose.position.y = step.pose.translation().y();
  o.pose.pose.position.z = step.pose.translation().z();
  o.pose.pose.orientation.w = q.w();
  o.pose.pose.orientation.x = q.x();
  o.pose.pose.orientation.y = q.y();
  o.pose.pose.orientation.z = q.z();
  const bool known = step.covariance.allFinite() && step.covariance.any();
  for (int r = 0; r < 6; ++r)
    for (int k = 0; k < 6; ++k)
      o.pose.covariance[static_cast<std::size_t>(6 * r + k)] = known ? step.covariance(r, k) : -1.0;
  o.twist.twist.linear.x = step.velocity.x();
  o.twist.twist.linear.y = step.velocity.y();
  o.twist.twist.linear.z = step.velocity.z();
  odom_.publish(o);
  tf2_msgs::TFMessage tf;
  geometry_msgs::TransformStamped t;
  t.header = o.header;
  t.child_frame_id = base_frame;
  t.transform.translation.x = step.pose.translation().x();
  t.transform.translation.y = step.pose.translation().y();
  t.transform.translation.z = step.pose.translation().z();
  t.transform.rotation = o.pose.pose.orientation;
  tf.transforms.push_back(t);
  tf_.publish(tf);
}

void Publishers::localMap(const pcl::PointCloud<PointRadar>& cloud, std::int64_t t_us, const std::string& frame) {
  publishCloud(local_map_, cloud, t_us, frame);
}

void Publishers::map(const pcl::PointCloud<PointRadar>& cloud, std::int64_t t_us, const std::string& frame) {
  publishCloud(map_, cloud, t_us, frame);
}

void Publishers::diagnostics(std::vector<diagnostic_msgs::DiagnosticStatus> status) {
  diagnostic_msgs::DiagnosticArray a;
  a.header.stamp = ros::Time::now();
  a.status = std::move(status);
  diag_.publish(a);
}

}  // namespace node
}  // namespace radar_ndt

#include "bag_reading.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TwistStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/view.h>
#include <sensor_msgs/Imu.h>
#include <tf2_msgs/TFMessage.h>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/ros/ros_time.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {
namespace ros1 {
namespace detail {

void openForWriting(rosbag::Bag& bag, const std::string& path, BagCompression compression) {
  bag.open(path, rosbag::bagmode::Write);
  bag.setCompression(compression == BagCompression::Bz2   ? rosbag::compression::BZ2
                     : compression == BagCompression::Lz4 ? rosbag::compression::LZ4
                                                          : rosbag::compression::Uncompressed);
}

nav_msgs::Odometry odometryMessage(const Eigen::Isometry3d& pose, const ros::Time& stamp, const std::string& parent,
                                   const std::string& child) {
  nav_msgs::Odometry o;
  o.header.stamp = stamp;
  o.header.frame_id = parent;
  o.child_frame_id = child;
  const Eigen::Quaterniond q(pose.linear());
  o.pose.pose.position.x = pose.translation().x();
  o.pose.pose.position.y = pose.translation().y();
  o.pose.pose.position.z = pose.translation().z();
  o.pose.pose.orientation.w = q.w();
  o.pose.pose.orientation.x = q.x();
  o.pose.pose.orientation.y = q.y();
  o.pose.pose.orientation.z = q.z();
  return o;
}

std::string seconds(const ros::Time& t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%u.%06u s", t.sec, t.nsec / 1000);
  return buf;
}

Eigen::Isometry3d toIsometry(double x, double y, double z, double qw, double qx, double qy, double qz,
                             const std::string& what) {
  Eigen::Quaterniond q(qw, qx, qy, qz);
  const double norm = q.norm();
  if (!(std::abs(norm - 1.0) < 1e-2) || !std::isfinite(x + y + z))
    throw std::invalid_argument(what + ": rotation quaternion has norm " + std::to_string(norm) +
                                " or the position is not finite");
  q.normalize();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() << x, y, z;
  return T;
}

namespace {

Eigen::Isometry3d poseToIsometry(const geometry_msgs::Pose& p, const std::string& what) {
  return toIsometry(p.position.x, p.position.y, p.position.z, p.orientation.w, p.orientation.x, p.orientation.y,
                    p.orientation.z, what);
}

Eigen::Isometry3d transformToIsometry(const geometry_msgs::Transform& t, const std::string& what) {
  return toIsometry(t.translation.x, t.translation.y, t.translation.z, t.rotation.w, t.rotation.x, t.rotation.y,
                    t.rotation.z, what);
}

bool hasBagMagic(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[13] = {};
  in.read(magic, sizeof magic);
  return in && std::string(magic, sizeof magic) == "#ROSBAG V2.0\n";
}

}  // namespace

void ProblemLog::add(const std::string& key, const std::string& text) {
  if (count_[key]++ < 3) lines_.push_back(text);
}

std::vector<std::string> ProblemLog::finish() {
  for (const auto& [key, n] : count_)
    if (n > 3) lines_.push_back(key + ": " + std::to_string(n - 3) + " more like these");
  return lines_;
}

OpenBag::OpenBag(const std::string& bag_path) : path(bag_path), bag(std::make_unique<rosbag::Bag>()) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw IoError(path, "no such bag file");
  try {
    bag->open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagUnindexedException&) {
    throw IoError(path, "the bag is unindexed (a recording that was cut off): run `rosbag reindex " + path +
                            "` and read it again");
  } catch (const rosbag::BagException& e) {
    if (hasBagMagic(path))  // a bag, cut off before its index (a recording that was killed)
      throw IoError(path, std::string("truncated or unindexed (") + e.what() + "): run `rosbag reindex " + path +
                              "` and read it again");
    throw IoError(path, std::string("not a readable ROS 1 bag (format 2.0): ") + e.what());
  }
  rosbag::View all(*bag);
  for (const rosbag::ConnectionInfo* c : all.getConnections()) types.emplace(c->topic, c->datatype);
}

std::string OpenBag::topicList() const {
  std::string list;
  for (const auto& [topic, type] : types) list += (list.empty() ? "" : ", ") + topic + " (" + type + ")";
  return list.empty() ? "none" : list;
}

void OpenBag::expectType(const std::string& description, const std::string& key, const std::string& topic,
                         const std::set<std::string>& wanted) const {
  const auto it = types.find(topic);
  std::string list;
  for (const auto& t : wanted) list += (list.empty() ? "" : " or ") + t;
  if (it == types.end())
    throw IoError(
        path, description + ": " + key + " topic " + topic + " is not in the bag (its topics: " + topicList() + ")");
  if (!wanted.count(it->second))
    throw IoError(path, key + " topic " + topic + " carries " + it->second + ", not " + list);
}

ros::Time StampRule::operator()(const ros::Time& header, const rosbag::MessageInstance& m,
                                std::vector<std::string>& problems) {
  if (source_ == StampSource::Receive) return m.getTime();
  if (source_ == StampSource::Auto && header.isZero()) {
    if (zero_stamps_.insert(m.getTopic()).second)
      problems.push_back(m.getTopic() +
                         ": header stamps are 0 (the driver writes none): the bag's receive "
                         "times are used");
    return m.getTime();
  }
  return header;
}

void MotionTopics::check(const OpenBag& bag) const {
  if (!d_.imu_topic.empty()) bag.expectType(d_.source, "imu", d_.imu_topic, {kImu});
  if (!d_.speed_topic.empty()) bag.expectType(d_.source, "speed", d_.speed_topic, {kTwistStamped, kOdometry});
  if (!d_.ground_truth_topic.empty())
    bag.expectType(d_.source, "ground_truth", d_.ground_truth_topic, {kOdometry, kPoseStamped, kTf});
}

std::vector<std::string> MotionTopics::topics(const OpenBag& bag) const {
  std::vector<std::string> out;
  for (const std::string& t :
       {d_.imu_topic, d_.speed_topic, d_.ground_truth_topic, std::string("/tf"), std::string("/tf_static")})
    if (!t.empty() && bag.types.count(t)) out.push_back(t);
  return out;
}

bool MotionTopics::take(const rosbag::MessageInstance& m, StampRule& stamps, std::vector<std::string>& problems) {
  const std::string& topic = m.getTopic();
  bool taken = false;
  if (topic == d_.imu_topic) {
    taken = true;
    const auto imu = m.instantiate<sensor_msgs::Imu>();
    const Eigen::Vector3d gyro(imu->angular_velocity.x, imu->angular_velocity.y, imu->angular_velocity.z);
    const double rate = imuYawRate(d_, gyro);
    // The first second's specific force in the base frame: gravity should read along +z.
    const Eigen::Vector3d f(imu->linear_acceleration.x, imu->linear_acceleration.y, imu->linear_acceleration.z);
    if (f.allFinite() && f.norm() > 1.0 && gravity_count_ < 200) {
      gravity_sum_ += imuRotation(d_) * f;
      ++gravity_count_;
    }
    if (!std::isfinite(rate)) {
      ++imu_dropped_;
    } else {
      ++imu_messages_;
      const std::int64_t t = microseconds(stamps(imu->header.stamp, m, problems));
      imu_.emplace_back(t, rate);
      if (gyro.allFinite() && f.allFinite())
        imu6_.push_back({static_cast<double>(t) * 1e-6, imuRotation(d_) * gyro, imuRotation(d_) * f});
    }
  }
  if (topic == d_.speed_topic) {
    const bool odometry = m.getDataType() == kOdometry;
    const auto o = odometry ? m.instantiate<nav_msgs::Odometry>() : nullptr;
    const auto t = odometry ? nullptr : m.instantiate<geometry_msgs::TwistStamped>();
    const double v = odometry ? o->twist.twist.linear.x : t->twist.linear.x;
    if (!std::isfinite(v))
      ++speed_dropped_;
    else
      speed_.emplace_back(microseconds(stamps(odometry ? o->header.stamp : t->header.stamp, m, problems)), v);
    if (topic == d_.ground_truth_topic) takePose(m, stamps, problems);  // one Odometry topic may be both
    return true;
  }
  if (topic == "/tf" || topic == "/tf_static" || (topic == d_.ground_truth_topic && m.getDataType() == kTf)) {
    takeTf(m);
    taken = true;
  } else if (topic == d_.ground_truth_topic) {
    takePose(m, stamps, problems);
    taken = true;
  }
  return taken;
}

void MotionTopics::takeTf(const rosbag::MessageInstance& m) {
  const auto tf = m.instantiate<tf2_msgs::TFMessage>();
  if (m.getTopic() == "/tf" || m.getTopic() == "/tf_static") {
    std::vector<std::string> bad;
    tree_.add(*tf, m.getTopic(), &bad);
    for (const std::string& b : bad) log_.add(m.getTopic() + " (bad transforms)", b);
  }
  for (const auto& t : tf->transforms) {
    try {
      if (m.getTopic() == d_.ground_truth_topic && t.header.frame_id == d_.ground_truth_parent &&
          t.child_frame_id == d_.ground_truth_child)
        poses_.emplace_back(microseconds(t.header.stamp), transformToIsometry(t.transform, m.getTopic()));
    } catch (const std::invalid_argument& e) {
      log_.add(m.getTopic() + " (bad transforms)", m.getTopic() + " at " + seconds(m.getTime()) + ": " + e.what());
    }
  }
}

void MotionTopics::takePose(const rosbag::MessageInstance& m, StampRule& stamps, std::vector<std::string>& problems) {
  try {
    if (m.getDataType() == kOdometry) {
      const auto o = m.instantiate<nav_msgs::Odometry>();
      poses_.emplace_back(microseconds(stamps(o->header.stamp, m, problems)),
                          poseToIsometry(o->pose.pose, m.getTopic()));
    } else {
      const auto p = m.instantiate<geometry_msgs::PoseStamped>();
      poses_.emplace_back(microseconds(stamps(p->header.stamp, m, problems)), poseToIsometry(p->pose, m.getTopic()));
    }
  } catch (const std::invalid_argument& e) {
    log_.add(m.getTopic() + " (bad poses)", m.getTopic() + " at " + seconds(m.getTime()) + ": " + e.what());
  }
}

namespace {

/// Samples sorted by stamp (stable), the first of a repeated stamp kept.
TimeSeries seriesOf(std::vector<std::pair<std::int64_t, double>>& samples) {
  std::stable_sort(samples.begin(), samples.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  TimeSeries s;
  for (const auto& [t, v] : samples) {
    if (!s.stamps_us.empty() && t == s.stamps_us.back()) continue;
    s.stamps_us.push_back(t);
    s.values.push_back(v);
  }
  return s;
}

}  // namespace

void MotionTopics::finish(std::shared_ptr<const VehicleSignals>& signals_out, Trajectory& ground_truth,
                          std::vector<std::string>& problems) {
  if (!d_.imu_topic.empty() || !d_.speed_topic.empty()) {
    auto signals = std::make_shared<VehicleSignals>();
    signals->source = path_ + ":" + (d_.imu_topic.empty() ? d_.speed_topic : d_.imu_topic);
    signals->dropped = imu_dropped_ + speed_dropped_;
    if (!d_.imu_topic.empty()) {
      signals->yaw_rate = seriesOf(imu_);
      if (signals->yaw_rate.empty())
        throw IoError(path_, "imu topic " + d_.imu_topic + " has no message with a yaw rate");
    }
    if (imu_dropped_ > 0)
      problems.push_back(d_.imu_topic + ": " + std::to_string(imu_dropped_) +
                         " messages without a finite yaw rate left out");
    // Gravity along another axis than the description's mounting says: the yaw rate would be
    // another axis's rate. Said with the figures; the run goes on.
    if (gravity_count_ > 0) {
      const Eigen::Vector3d g = gravity_sum_ / static_cast<double>(gravity_count_);
      const double tilt = std::acos(std::clamp(g.normalized().z(), -1.0, 1.0)) * 180.0 / kPi;
      if (tilt > 45.0) {
        char text[320];
        std::snprintf(text, sizeof text,
                      "%s: the accelerometer reads gravity along (%.2f, %.2f, %.2f) m/s^2 in the base frame, %.0f "
                      "degrees from its z (up): the IMU is not mounted as described, and its yaw rate is another "
                      "axis's; give 'imu_mounting' (the IMU's roll pitch yaw in the base frame)",
                      d_.imu_topic.c_str(), g.x(), g.y(), g.z(), tilt);
        problems.push_back(text);
      }
    }
    if (!d_.speed_topic.empty()) {
      signals->speed = seriesOf(speed_);
      if (signals->speed.empty()) throw IoError(path_, "speed topic " + d_.speed_topic + " has no finite speed");
    }
    if (speed_dropped_ > 0)
      problems.push_back(d_.speed_topic + ": " + std::to_string(speed_dropped_) +
                         " messages without a finite speed left out");
    signals_out = std::move(signals);
  }
  std::stable_sort(poses_.begin(), poses_.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [t, pose] : poses_) {
    const double stamp = 1e-6 * static_cast<double>(t);
    if (!ground_truth.stamps.empty() && !(stamp > ground_truth.stamps.back())) continue;
    ground_truth.stamps.push_back(stamp);
    ground_truth.poses.push_back(pose);
  }
  if (!d_.ground_truth_topic.empty() && ground_truth.empty())
    problems.push_back(d_.ground_truth_topic + ": no ground-truth pose " + d_.ground_truth_parent + " -> " +
                       d_.ground_truth_child + " in the bag: the run cannot be evaluated");
}

}  // namespace detail
}  // namespace ros1
}  // namespace radar_ndt

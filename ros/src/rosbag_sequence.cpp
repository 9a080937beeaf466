#include "radar_ndt/ros/rosbag_sequence.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/ros/point_cloud2.h"
#include "radar_ndt/ros/ros_time.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {
namespace ros1 {

namespace {

constexpr const char* kCloud = "sensor_msgs/PointCloud2";
constexpr const char* kImu = "sensor_msgs/Imu";
constexpr const char* kOdometry = "nav_msgs/Odometry";
constexpr const char* kPoseStamped = "geometry_msgs/PoseStamped";
constexpr const char* kTf = "tf2_msgs/TFMessage";

std::string seconds(const ros::Time& t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%u.%06u s", t.sec, t.nsec / 1000);
  return buf;
}

/// A position and quaternion as an isometry, as the nuScenes tables are read (quaternion
/// normalised; one far from unit norm is refused), so that a bag written from a scene gives the
/// scene's transforms to the last bit.
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

Eigen::Isometry3d toIsometry(const geometry_msgs::Pose& p, const std::string& what) {
  return toIsometry(p.position.x, p.position.y, p.position.z, p.orientation.w, p.orientation.x, p.orientation.y,
                    p.orientation.z, what);
}

Eigen::Isometry3d toIsometry(const geometry_msgs::Transform& t, const std::string& what) {
  return toIsometry(t.translation.x, t.translation.y, t.translation.z, t.rotation.w, t.rotation.x, t.rotation.y,
                    t.rotation.z, what);
}

/// Problems of one kind said at most a few times, then counted.
class ProblemLog {
 public:
  void add(const std::string& key, const std::string& text) {
    if (count_[key]++ < 3) lines_.push_back(text);
  }
  std::vector<std::string> finish() {
    for (const auto& [key, n] : count_)
      if (n > 3) lines_.push_back(key + ": " + std::to_string(n - 3) + " more like these");
    return lines_;
  }

 private:
  std::map<std::string, std::size_t> count_;
  std::vector<std::string> lines_;
};

}  // namespace

/// Reads a bag into a RosbagRadarSequence: one pass over the described topics in time order.
class BagReader {
 public:
  BagReader(RosbagRadarSequence& s, const SensorDescription& d) : s_(s), d_(d) {}

  void read() {
    rosbag::Bag bag;
    open(bag);
    checkTopics(bag);
    std::vector<std::string> topics;
    for (const auto& r : d_.radars) topics.push_back(r.topic);
    for (const std::string& t : {d_.imu_topic, d_.ground_truth_topic, std::string("/tf"), std::string("/tf_static")})
      if (!t.empty() && types_.count(t) && std::find(topics.begin(), topics.end(), t) == topics.end())
        topics.push_back(t);
    try {
      rosbag::View view(bag, rosbag::TopicQuery(topics));
      for (const rosbag::MessageInstance& m : view) take(m);
    } catch (const rosbag::BagException& e) {
      throw IoError(s_.path_, std::string("cannot read its messages (truncated or corrupt: try `rosbag reindex ") +
                                  s_.path_ + "`): " + e.what());
    }
    finish();
  }

 private:
  void open(rosbag::Bag& bag) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(s_.path_, ec)) throw IoError(s_.path_, "no such bag file");
    try {
      bag.open(s_.path_, rosbag::bagmode::Read);
    } catch (const rosbag::BagUnindexedException&) {
      throw IoError(s_.path_, "the bag is unindexed (a recording that was cut off): run `rosbag reindex " + s_.path_ +
                                  "` and read it again");
    } catch (const rosbag::BagException& e) {
      if (hasBagMagic())  // a bag, cut off before its index (a recording that was killed)
        throw IoError(s_.path_, std::string("truncated or unindexed (") + e.what() + "): run `rosbag reindex " +
                                    s_.path_ + "` and read it again");
      throw IoError(s_.path_, std::string("not a readable ROS 1 bag (format 2.0): ") + e.what());
    }
    rosbag::View all(bag);
    for (const rosbag::ConnectionInfo* c : all.getConnections()) types_.emplace(c->topic, c->datatype);
  }

  bool hasBagMagic() const {
    std::ifstream in(s_.path_, std::ios::binary);
    char magic[13] = {};
    in.read(magic, sizeof magic);
    return in && std::string(magic, sizeof magic) == "#ROSBAG V2.0\n";
  }

  std::string topicList() const {
    std::string list;
    for (const auto& [topic, type] : types_) list += (list.empty() ? "" : ", ") + topic + " (" + type + ")";
    return list.empty() ? "none" : list;
  }

  void expectType(const std::string& key, const std::string& topic, const std::set<std::string>& types) const {
    const auto it = types_.find(topic);
    std::string wanted;
    for (const auto& t : types) wanted += (wanted.empty() ? "" : " or ") + t;
    if (it == types_.end())
      throw IoError(s_.path_, d_.source + ": " + key + " topic " + topic +
                                  " is not in the bag (its topics: " + topicList() + ")");
    if (!types.count(it->second))
      throw IoError(s_.path_, key + " topic " + topic + " carries " + it->second + ", not " + wanted);
  }

  void checkTopics(const rosbag::Bag&) {
    for (std::size_t i = 0; i < d_.radars.size(); ++i) {
      const RadarDescription& r = d_.radars[i];
      if (r.kind == RadarKind::Scanning)
        throw IoError(s_.path_, d_.source + ": radar " + r.name +
                                    " is a scanning radar: polar scans are not read from ROS bags yet (docs/ros.md)");
      if (r.fields.doppler == DopplerKind::None)
        throw IoError(s_.path_, d_.source + ": radar " + r.name +
                                    " has no Doppler field: the automotive pipeline needs the radial velocity");
      expectType("radar " + r.name, r.topic, {kCloud});
      s_.channels_.push_back(r.name);
    }
    if (!d_.imu_topic.empty()) expectType("imu", d_.imu_topic, {kImu});
    if (!d_.ground_truth_topic.empty())
      expectType("ground_truth", d_.ground_truth_topic, {kOdometry, kPoseStamped, kTf});
    frames_.assign(d_.radars.size(), "");
    for (std::size_t i = 0; i < d_.radars.size(); ++i) frames_[i] = d_.radars[i].frame;
    read_ok_.assign(d_.radars.size(), 0);
    first_error_.assign(d_.radars.size(), "");
  }

  /// A message's time as the description says: its header stamp, or the bag's receive time.
  ros::Time stampOf(const ros::Time& header, const rosbag::MessageInstance& m) {
    if (d_.stamps == StampSource::Receive) return m.getTime();
    if (d_.stamps == StampSource::Auto && header.isZero()) {
      if (zero_stamps_.insert(m.getTopic()).second)
        s_.problems_.push_back(m.getTopic() +
                               ": header stamps are 0 (the driver writes none): the bag's receive "
                               "times are used");
      return m.getTime();
    }
    return header;
  }

  void take(const rosbag::MessageInstance& m) {
    const std::string& topic = m.getTopic();
    for (std::size_t i = 0; i < d_.radars.size(); ++i)
      if (d_.radars[i].topic == topic) takeRadar(m, static_cast<std::uint16_t>(i));
    if (topic == d_.imu_topic) takeImu(m);
    if (topic == "/tf" || topic == "/tf_static" || (topic == d_.ground_truth_topic && m.getDataType() == kTf))
      takeTf(m);
    else if (topic == d_.ground_truth_topic)
      takePose(m);
  }

  void takeRadar(const rosbag::MessageInstance& m, std::uint16_t channel) {
    ++s_.stats_.radar_messages;
    const RadarDescription& r = d_.radars[channel];
    const auto cloud = m.instantiate<sensor_msgs::PointCloud2>();
    const ros::Time t = stampOf(cloud->header.stamp, m);
    try {
      if (frames_[channel].empty()) frames_[channel] = cloud->header.frame_id;
      const std::vector<std::string> names = r.fields.columns();
      const CloudColumns columns = readCloudColumns(*cloud, names);
      for (const std::string& required : r.fields.requiredColumns())
        for (std::size_t c = 0; c < names.size(); ++c)
          if (names[c] == required && !columns.present[c])
            throw std::invalid_argument("no field '" + required + "' (the message's fields: " + fieldNames(*cloud) +
                                        ")");
      RadarPointStats stats;
      RosbagRadarSequence::Sweep sweep;
      sweep.points = convertRadarPoints(columns.table, columns.points, columns.present, r.fields, channel, &stats);
      sweep.timestamp_us = microseconds(t);
      sweep.channel = channel;
      sweep.non_finite = stats.dropped_non_finite;
      s_.stats_.non_finite_dropped += stats.dropped_non_finite;
      s_.sweeps_.push_back(std::move(sweep));
      read_ok_[channel] = 1;
    } catch (const std::invalid_argument& e) {
      ++s_.stats_.unreadable_messages;
      const std::string text = r.topic + " at " + seconds(t) + ": " + e.what() + ": left out";
      if (first_error_[channel].empty()) first_error_[channel] = text;
      log_.add(r.topic + " (malformed clouds)", text);
    }
  }

  void takeImu(const rosbag::MessageInstance& m) {
    const auto imu = m.instantiate<sensor_msgs::Imu>();
    const double rate = imu->angular_velocity.z;
    if (!std::isfinite(rate)) {
      ++imu_dropped_;
      return;
    }
    ++s_.stats_.imu_messages;
    imu_.emplace_back(microseconds(stampOf(imu->header.stamp, m)), rate);
  }

  void takeTf(const rosbag::MessageInstance& m) {
    const auto tf = m.instantiate<tf2_msgs::TFMessage>();
    for (const auto& t : tf->transforms) {
      try {
        if (t.header.frame_id == d_.base_frame && !edges_.count(t.child_frame_id))
          edges_.emplace(t.child_frame_id, toIsometry(t.transform, m.getTopic() + " " + t.child_frame_id));
        if (m.getTopic() == d_.ground_truth_topic && t.header.frame_id == d_.ground_truth_parent &&
            t.child_frame_id == d_.ground_truth_child)
          addPose(microseconds(t.header.stamp), toIsometry(t.transform, m.getTopic()));
      } catch (const std::invalid_argument& e) {
        log_.add(m.getTopic() + " (bad transforms)", m.getTopic() + " at " + seconds(m.getTime()) + ": " + e.what());
      }
    }
  }

  void takePose(const rosbag::MessageInstance& m) {
    try {
      if (m.getDataType() == kOdometry) {
        const auto o = m.instantiate<nav_msgs::Odometry>();
        addPose(microseconds(stampOf(o->header.stamp, m)), toIsometry(o->pose.pose, m.getTopic()));
      } else {
        const auto p = m.instantiate<geometry_msgs::PoseStamped>();
        addPose(microseconds(stampOf(p->header.stamp, m)), toIsometry(p->pose, m.getTopic()));
      }
    } catch (const std::invalid_argument& e) {
      log_.add(m.getTopic() + " (bad poses)", m.getTopic() + " at " + seconds(m.getTime()) + ": " + e.what());
    }
  }

  void addPose(std::int64_t t_us, const Eigen::Isometry3d& pose) { poses_.emplace_back(t_us, pose); }

  void finish();
  void finishMountings();
  void finishSignalsAndTruth();

  RosbagRadarSequence& s_;
  const SensorDescription& d_;
  std::map<std::string, std::string> types_;
  std::vector<std::string> frames_, first_error_;
  std::vector<char> read_ok_;
  std::set<std::string> zero_stamps_;
  std::map<std::string, Eigen::Isometry3d> edges_;  ///< base frame → child frame, first seen
  std::vector<std::pair<std::int64_t, double>> imu_;
  std::vector<std::pair<std::int64_t, Eigen::Isometry3d>> poses_;
  std::size_t imu_dropped_ = 0;
  ProblemLog log_;
};

void BagReader::finishMountings() {
  for (std::size_t i = 0; i < d_.radars.size(); ++i) {
    const RadarDescription& r = d_.radars[i];
    if (r.mounting) {
      s_.mountings_.push_back(r.mounting->transform());
      continue;
    }
    if (frames_[i].empty())
      throw IoError(s_.path_, d_.source + ": radar " + r.name +
                                  " has no mounting: its messages name no frame and the description neither; give "
                                  "its 'mounting' (x y z roll pitch yaw)");
    const auto edge = edges_.find(frames_[i]);
    if (edge == edges_.end())
      throw IoError(s_.path_, d_.source + ": radar " + r.name + ": no transform " + d_.base_frame + " -> " +
                                  frames_[i] + " in /tf_static or /tf; give its 'mounting' (x y z roll pitch yaw)");
    s_.mountings_.push_back(edge->second);
  }
}

void BagReader::finishSignalsAndTruth() {
  if (!d_.imu_topic.empty()) {
    std::stable_sort(imu_.begin(), imu_.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    auto signals = std::make_shared<VehicleSignals>();
    signals->source = s_.path_ + ":" + d_.imu_topic;
    signals->dropped = imu_dropped_;
    for (const auto& [t, v] : imu_) {
      if (!signals->yaw_rate.stamps_us.empty() && t == signals->yaw_rate.stamps_us.back()) continue;
      signals->yaw_rate.stamps_us.push_back(t);
      signals->yaw_rate.values.push_back(v);
    }
    if (signals->yaw_rate.empty())
      throw IoError(s_.path_, "imu topic " + d_.imu_topic + " has no message with a yaw rate");
    if (imu_dropped_ > 0)
      s_.problems_.push_back(d_.imu_topic + ": " + std::to_string(imu_dropped_) +
                             " messages without a finite yaw rate left out");
    s_.signals_ = std::move(signals);
  }
  std::stable_sort(poses_.begin(), poses_.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [t, pose] : poses_) {
    const double stamp = 1e-6 * static_cast<double>(t);
    if (!s_.ground_truth_.stamps.empty() && !(stamp > s_.ground_truth_.stamps.back())) continue;
    s_.ground_truth_.stamps.push_back(stamp);
    s_.ground_truth_.poses.push_back(pose);
  }
  s_.stats_.ground_truth_poses = s_.ground_truth_.size();
  if (!d_.ground_truth_topic.empty() && s_.ground_truth_.empty())
    s_.problems_.push_back(d_.ground_truth_topic + ": no ground-truth pose " + d_.ground_truth_parent + " -> " +
                           d_.ground_truth_child + " in the bag: the run cannot be evaluated");
}

void BagReader::finish() {
  for (std::size_t i = 0; i < d_.radars.size(); ++i)
    if (!read_ok_[i])
      throw IoError(s_.path_,
                    "radar " + d_.radars[i].name + ": " +
                        (first_error_[i].empty() ? "no message on " + d_.radars[i].topic
                                                 : "no message could be read; the first: " + first_error_[i]));
  finishMountings();
  finishSignalsAndTruth();
  // Time order, channel order at equal times (as a nuScenes scene's sweeps); a radar's repeated
  // stamp (a message recorded twice) is left out.
  auto& sweeps = s_.sweeps_;
  std::stable_sort(sweeps.begin(), sweeps.end(), [](const auto& a, const auto& b) {
    return a.timestamp_us != b.timestamp_us ? a.timestamp_us < b.timestamp_us : a.channel < b.channel;
  });
  std::vector<RosbagRadarSequence::Sweep> kept;
  for (auto& sw : sweeps) {
    if (!kept.empty() && kept.back().timestamp_us == sw.timestamp_us && kept.back().channel == sw.channel) {
      log_.add(
          d_.radars[sw.channel].topic + " (repeated stamps)",
          d_.radars[sw.channel].topic + ": a second message at " + std::to_string(sw.timestamp_us) + " us: left out");
      continue;
    }
    kept.push_back(std::move(sw));
  }
  sweeps.swap(kept);
  for (const std::string& p : log_.finish()) s_.problems_.push_back(p);
  std::map<std::uint16_t, SensorMounting> mountings;
  std::vector<SweepStamp> stamps;
  for (const auto& sw : sweeps) {
    stamps.push_back({sw.timestamp_us, sw.channel});
    if (!mountings.count(sw.channel)) mountings[sw.channel] = toMounting(s_.mountings_[sw.channel]);
  }
  const std::uint16_t ref = chooseReferenceChannel(mountings, s_.channels_, d_.reference, s_.path_);
  s_.reference_channel_ = s_.channels_[ref];
  s_.plans_ = planRadarCycles(stamps, ref);
  s_.silences_ = findRadarSilences(stamps, s_.channels_);
  if (s_.plans_.size() >= 2)
    s_.period_s_ = 1e-6 * static_cast<double>(s_.timestamp(s_.plans_.size() - 1) - s_.timestamp(0)) /
                   static_cast<double>(s_.plans_.size() - 1);
}

RosbagRadarSequence::RosbagRadarSequence(const std::string& bag_path, const SensorDescription& sensors)
    : path_(bag_path), name_(std::filesystem::path(bag_path).stem().string()) {
  BagReader(*this, sensors).read();
}

Trajectory RosbagRadarSequence::groundTruthTrajectory() const {
  Trajectory t;
  std::optional<Pose2> first;
  for (std::size_t k = 0; k < plans_.size(); ++k) {
    const double stamp = 1e-6 * static_cast<double>(timestamp(k));
    Eigen::Isometry3d pose;
    if (!ground_truth_.poseAt(stamp, &pose)) continue;
    if (!first) first = toPose2(pose);
    t.stamps.push_back(stamp);
    t.poses.push_back(toIsometry3(between(*first, toPose2(pose))));
  }
  return t;
}

RadarCycle RosbagRadarSequence::load(std::size_t k, std::vector<std::string>* problems,
                                     std::size_t* non_finite_dropped) const {
  RadarCycle cycle;
  cycle.timestamp_us = timestamp(k);
  for (const std::size_t i : plans_[k].members) {
    const Sweep& s = sweeps_[i];
    RadarSweepData d;
    d.timestamp_us = s.timestamp_us;
    d.sensor_id = s.channel;
    d.sensor_to_vehicle = mountings_[s.channel];
    d.points = s.points;
    if (non_finite_dropped) *non_finite_dropped += s.non_finite;
    if (problems && s.non_finite > 0)
      problems->push_back(channels_[s.channel] + " at " + std::to_string(s.timestamp_us) + " us: dropped " +
                          std::to_string(s.non_finite) + " points with NaN or Inf values");
    cycle.sweeps.push_back(std::move(d));
  }
  return cycle;
}

}  // namespace ros1
}  // namespace radar_ndt

#include "radar_ndt/ros/rosbag_sequence.h"

#include "bag_reading.h"

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
#include <sensor_msgs/PointCloud.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/ros/point_cloud2.h"
#include "radar_ndt/ros/ros_time.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {
namespace ros1 {

using namespace detail;

/// Reads a bag into a RosbagRadarSequence: one pass over the described topics in time order.
class BagReader {
 public:
  BagReader(RosbagRadarSequence& s, const SensorDescription& d)
      : s_(s), d_(d), stamps_(d.stamps), motion_(d, s.path_) {}

  void read() {
    OpenBag bag(s_.path_);
    checkTopics(bag);
    std::vector<std::string> topics;
    for (const auto& r : d_.radars) topics.push_back(r.topic);
    for (const std::string& t : motion_.topics(bag))
      if (std::find(topics.begin(), topics.end(), t) == topics.end()) topics.push_back(t);
    try {
      rosbag::View view(*bag.bag, rosbag::TopicQuery(topics));
      for (const rosbag::MessageInstance& m : view) take(m);
    } catch (const rosbag::BagException& e) {
      throw IoError(s_.path_, std::string("cannot read its messages (truncated or corrupt: try `rosbag reindex ") +
                                  s_.path_ + "`): " + e.what());
    }
    finish();
  }

 private:
  void checkTopics(const OpenBag& bag) {
    for (std::size_t i = 0; i < d_.radars.size(); ++i) {
      const RadarDescription& r = d_.radars[i];
      if (r.kind == RadarKind::Scanning)
        throw IoError(s_.path_, d_.source + ": radar " + r.name +
                                    " is a scanning radar: the automotive pipeline reads point clouds (a "
                                    "scanning radar's bag is run with --format rosbag as well: one radar, kind "
                                    "scanning, docs/ros.md)");
      if (r.fields.doppler == DopplerKind::None)
        throw IoError(s_.path_, d_.source + ": radar " + r.name +
                                    " has no Doppler field: the automotive pipeline needs the radial velocity");
      bag.expectType(d_.source, "radar " + r.name, r.topic, {kCloud, kCloud1});
      s_.channels_.push_back(r.name);
    }
    motion_.check(bag);
    frames_.assign(d_.radars.size(), "");
    for (std::size_t i = 0; i < d_.radars.size(); ++i) frames_[i] = d_.radars[i].frame;
    read_ok_.assign(d_.radars.size(), 0);
    first_error_.assign(d_.radars.size(), "");
  }

  void take(const rosbag::MessageInstance& m) {
    const std::string& topic = m.getTopic();
    for (std::size_t i = 0; i < d_.radars.size(); ++i)
      if (d_.radars[i].topic == topic) takeRadar(m, static_cast<std::uint16_t>(i));
    motion_.take(m, stamps_, s_.problems_);
  }

  void takeRadar(const rosbag::MessageInstance& m, std::uint16_t channel) {
    ++s_.stats_.radar_messages;
    const RadarDescription& r = d_.radars[channel];
    // sensor_msgs/PointCloud2, or the first PointCloud some 4D radar drivers publish.
    const auto cloud = m.instantiate<sensor_msgs::PointCloud2>();
    const auto cloud1 = cloud ? nullptr : m.instantiate<sensor_msgs::PointCloud>();
    const std_msgs::Header& header = cloud ? cloud->header : cloud1->header;
    const ros::Time t = stamps_(header.stamp, m, s_.problems_);
    try {
      if (frames_[channel].empty()) frames_[channel] = header.frame_id;
      const std::vector<std::string> names = r.fields.columns();
      const CloudColumns columns = cloud ? readCloudColumns(*cloud, names) : readCloudColumns(*cloud1, names);
      for (const std::string& required : r.fields.requiredColumns())
        for (std::size_t c = 0; c < names.size(); ++c)
          if (names[c] == required && !columns.present[c])
            throw std::invalid_argument("no field '" + required + "' (the message's fields: " +
                                        (cloud ? fieldNames(*cloud) : fieldNames(*cloud1)) + ")");
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
      motion_.log().add(r.topic + " (malformed clouds)", text);
    }
  }

  void finish();
  void finishMountings();

  RosbagRadarSequence& s_;
  const SensorDescription& d_;
  StampRule stamps_;
  MotionTopics motion_;
  std::vector<std::string> frames_, first_error_;
  std::vector<char> read_ok_;
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
    std::string why;
    const std::optional<Eigen::Isometry3d> mounting = motion_.mounting(frames_[i], &why);
    if (!mounting)
      throw IoError(s_.path_,
                    d_.source + ": radar " + r.name + ": " + why + "; give its 'mounting' (x y z roll pitch yaw)");
    s_.mountings_.push_back(*mounting);
  }
}

void BagReader::finish() {
  for (std::size_t i = 0; i < d_.radars.size(); ++i)
    if (!read_ok_[i])
      throw IoError(s_.path_,
                    "radar " + d_.radars[i].name + ": " +
                        (first_error_[i].empty() ? "no message on " + d_.radars[i].topic
                                                 : "no message could be read; the first: " + first_error_[i]));
  finishMountings();
  motion_.finish(s_.signals_, s_.ground_truth_, s_.problems_);
  s_.imu_ = motion_.takeImuSamples();
  s_.stats_.imu_messages = motion_.imuMessages();
  s_.stats_.ground_truth_poses = s_.ground_truth_.size();
  // Time order, channel order at equal times (as a nuScenes scene's sweeps); a radar's repeated
  // stamp (a message recorded twice) is left out.
  auto& sweeps = s_.sweeps_;
  std::stable_sort(sweeps.begin(), sweeps.end(), [](const auto& a, const auto& b) {
    return a.timestamp_us != b.timestamp_us ? a.timestamp_us < b.timestamp_us : a.channel < b.channel;
  });
  std::vector<RosbagRadarSequence::Sweep> kept;
  for (auto& sw : sweeps) {
    if (!kept.empty() && kept.back().timestamp_us == sw.timestamp_us && kept.back().channel == sw.channel) {
      motion_.log().add(
          d_.radars[sw.channel].topic + " (repeated stamps)",
          d_.radars[sw.channel].topic + ": a second message at " + std::to_string(sw.timestamp_us) + " us: left out");
      continue;
    }
    kept.push_back(std::move(sw));
  }
  sweeps.swap(kept);
  for (const std::string& p : motion_.log().finish()) s_.problems_.push_back(p);
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

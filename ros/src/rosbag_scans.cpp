#include "radar_ndt/ros/rosbag_scans.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>

#include <rosbag/view.h>
#include <sensor_msgs/Image.h>

#include "bag_reading.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/ros/ros_time.h"

namespace radar_ndt {
namespace ros1 {

using namespace detail;

void checkPolarImage(const std::string& encoding, std::uint32_t height, std::uint32_t width, std::uint32_t step,
                     std::size_t data_size) {
  if (encoding != "mono8" && encoding != "8UC1")
    throw std::invalid_argument("encoding '" + encoding + "': a polar image is 8 bits a bin (mono8 or 8UC1)");
  if (height == 0 || width == 0) throw std::invalid_argument("an empty image");
  if (step < width || data_size < static_cast<std::size_t>(step) * height)
    throw std::invalid_argument("data of " + std::to_string(data_size) + " bytes is shorter than " +
                                std::to_string(height) + " rows of " + std::to_string(step) + " (width " +
                                std::to_string(width) + ")");
}

PolarScan polarScanFromImage(const std::string& encoding, std::uint32_t height, std::uint32_t width, std::uint32_t step,
                             const std::vector<std::uint8_t>& data, std::int64_t stamp_us, std::int64_t period_us,
                             const PolarImageDescription& polar) {
  checkPolarImage(encoding, height, width, step, data.size());
  PolarScan scan;
  scan.azimuths = static_cast<int>(polar.rows_are_azimuths ? height : width);
  const int bins_in_image = static_cast<int>(polar.rows_are_azimuths ? width : height);
  scan.range_resolution = polar.convention.range_resolution;
  scan.range_offset_bins = polar.convention.range_offset_bins;
  scan.bins = bins_in_image;
  if (polar.max_range > 0)  // the bins within max_range: (b + offset) · resolution <= max_range
    scan.bins =
        std::clamp(static_cast<int>(std::floor(polar.max_range / scan.range_resolution - scan.range_offset_bins)) + 1,
                   1, bins_in_image);
  scan.power.resize(static_cast<std::size_t>(scan.azimuths) * static_cast<std::size_t>(scan.bins));
  for (int a = 0; a < scan.azimuths; ++a) {
    std::uint8_t* row = scan.row(a);
    if (polar.rows_are_azimuths) {
      std::copy_n(data.data() + static_cast<std::size_t>(a) * step, scan.bins, row);
    } else {
      for (int b = 0; b < scan.bins; ++b) row[b] = data[static_cast<std::size_t>(b) * step + a];
    }
  }
  const double n = scan.azimuths;
  const double kTwoPi = 2.0 * std::acos(-1.0);
  scan.angle.resize(scan.azimuths);
  scan.stamp_us.resize(scan.azimuths);
  scan.measured.assign(scan.azimuths, 1);
  for (int a = 0; a < scan.azimuths; ++a) {
    scan.angle[a] = polar.convention.toVehicleAngle(kTwoPi * (a + polar.azimuth_offset) / n);
    // The header stamp at `stamp_position` of the sweep (0: its first azimuth, 1: its last).
    const double from_stamp = (a - polar.stamp_position * (n - 1.0)) / n;
    scan.stamp_us[a] = stamp_us + static_cast<std::int64_t>(std::llround(from_stamp * static_cast<double>(period_us)));
  }
  scan.stamp = stamp_us;
  return scan;
}

struct RosbagScanSequence::Impl {
  explicit Impl(const std::string& path) : bag(path) {}
  OpenBag bag;
  std::string name, topic;
  PolarImageDescription polar;
  std::vector<rosbag::MessageInstance> messages;  ///< the sweeps, in stamp order
  std::vector<std::int64_t> stamps;
  std::int64_t period_us = 0, sweep_us = 0;
  Trajectory ground_truth;
  std::shared_ptr<const VehicleSignals> signals;
  std::vector<std::string> problems;
  BagReadStats stats;
  std::string no_gyro;
  mutable std::mutex read_lock;  ///< rosbag::Bag reads from one thread at a time

  /// The sweeps read (`sweeps`: stamp and index into `read`) in stamp order, a repeated stamp's
  /// second message left out and said; the period their median interval.
  void keepInStampOrder(std::vector<std::pair<std::int64_t, std::size_t>> sweeps,
                        const std::vector<rosbag::MessageInstance>& read, MotionTopics& motion) {
    std::stable_sort(sweeps.begin(), sweeps.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [t, i] : sweeps) {
      if (!stamps.empty() && t == stamps.back()) {
        motion.log().add(topic + " (repeated stamps)",
                         topic + ": a second message at " + std::to_string(t) + " us: left out");
        continue;
      }
      stamps.push_back(t);
      messages.push_back(read[i]);
    }
    std::vector<std::int64_t> intervals;
    for (std::size_t k = 1; k < stamps.size(); ++k) intervals.push_back(stamps[k] - stamps[k - 1]);
    if (!intervals.empty()) {
      std::nth_element(intervals.begin(), intervals.begin() + intervals.size() / 2, intervals.end());
      period_us = intervals[intervals.size() / 2];
    }
  }
};

RosbagScanSequence::RosbagScanSequence(const std::string& bag_path, const SensorDescription& d)
    : impl_(std::make_unique<Impl>(bag_path)) {
  Impl& s = *impl_;
  s.name = std::filesystem::path(bag_path).stem().string();
  if (d.radars.size() != 1 || d.radars[0].kind != RadarKind::Scanning)
    throw IoError(bag_path, d.source + ": a scanning run reads one radar of kind scanning");
  const RadarDescription& r = d.radars[0];
  s.topic = r.topic;
  s.polar = r.polar;
  s.bag.expectType(d.source, "radar " + r.name, r.topic, {kImage});
  MotionTopics motion(d, bag_path);
  motion.check(s.bag);
  StampRule stamps(d.stamps);
  std::vector<std::string> topics{r.topic};
  for (const std::string& t : motion.topics(s.bag))
    if (t != r.topic) topics.push_back(t);
  std::vector<rosbag::MessageInstance> read;                 // in the bag's order
  std::vector<std::pair<std::int64_t, std::size_t>> sweeps;  // stamp, index into `read`
  std::string first_error;
  try {
    rosbag::View view(*s.bag.bag, rosbag::TopicQuery(topics));
    for (const rosbag::MessageInstance& m : view) {
      if (m.getTopic() != r.topic) {
        motion.take(m, stamps, s.problems);
        continue;
      }
      ++s.stats.radar_messages;
      // The header is all that is needed now; the image is decoded again when the run asks for it.
      const auto image = m.instantiate<sensor_msgs::Image>();
      const ros::Time t = stamps(image->header.stamp, m, s.problems);
      try {
        checkPolarImage(image->encoding, image->height, image->width, image->step, image->data.size());
      } catch (const std::invalid_argument& e) {
        ++s.stats.unreadable_messages;
        const std::string text = r.topic + " at " + seconds(t) + ": " + e.what() + ": left out";
        if (first_error.empty()) first_error = text;
        motion.log().add(r.topic + " (malformed images)", text);
        continue;
      }
      sweeps.emplace_back(microseconds(t), read.size());
      read.push_back(m);
    }
  } catch (const rosbag::BagException& e) {
    throw IoError(bag_path, std::string("cannot read its messages (truncated or corrupt: try `rosbag reindex ") +
                                bag_path + "`): " + e.what());
  }
  if (sweeps.empty())
    throw IoError(bag_path, "radar " + r.name + ": " +
                                (first_error.empty() ? "no message on " + r.topic
                                                     : "no message could be read; the first: " + first_error));
  motion.finish(s.signals, s.ground_truth, s.problems);
  s.stats.imu_messages = motion.imuMessages();
  s.stats.ground_truth_poses = s.ground_truth.size();
  if (d.imu_topic.empty()) s.no_gyro = "--imu: " + d.source + " names no imu topic";
  s.keepInStampOrder(std::move(sweeps), read, motion);
  for (const std::string& p : motion.log().finish()) s.problems.push_back(p);
  // The azimuths' times spread over one turn: the described one, else the sweeps' interval.
  s.sweep_us = s.polar.sweep_period > 0 ? std::llround(s.polar.sweep_period * 1e6) : s.period_us;
}

RosbagScanSequence::~RosbagScanSequence() = default;

std::size_t RosbagScanSequence::size() const {
  return impl_->stamps.size();
}
std::int64_t RosbagScanSequence::stamp(std::size_t k) const {
  return impl_->stamps[k];
}
double RosbagScanSequence::periodSeconds() const {
  return 1e-6 * static_cast<double>(impl_->period_us);
}
const std::string& RosbagScanSequence::name() const {
  return impl_->name;
}
const Trajectory& RosbagScanSequence::groundTruth() const {
  return impl_->ground_truth;
}
const std::vector<std::string>& RosbagScanSequence::indexProblems() const {
  return impl_->problems;
}
const BagReadStats& RosbagScanSequence::stats() const {
  return impl_->stats;
}

std::string RosbagScanSequence::scanName(std::size_t k) const {
  return impl_->bag.path + ":" + impl_->topic + " at " + std::to_string(impl_->stamps[k]) + " us";
}

std::optional<VehicleSignals> RosbagScanSequence::gyro(std::string* why_not) const {
  if (!impl_->signals) {
    if (why_not) *why_not = impl_->no_gyro;
    return std::nullopt;
  }
  return *impl_->signals;
}

PolarScan RosbagScanSequence::load(std::size_t k) const {
  const Impl& s = *impl_;
  boost::shared_ptr<sensor_msgs::Image> image;
  try {
    std::lock_guard<std::mutex> lock(s.read_lock);
    image = s.messages[k].instantiate<sensor_msgs::Image>();
  } catch (const std::exception& e) {
    throw IoError(scanName(k), std::string("cannot be read: ") + e.what());
  }
  try {
    return polarScanFromImage(image->encoding, image->height, image->width, image->step, image->data, s.stamps[k],
                              s.sweep_us, s.polar);
  } catch (const std::invalid_argument& e) {
    throw IoError(scanName(k), e.what());
  }
}

}  // namespace ros1
}  // namespace radar_ndt

#pragma once
// What reading any bag through a sensor description shares (the radar cycles' reader and the
// polar scans'): opening it with clear errors, its topics' types, the stamp rule, and the IMU and
// ground truth the description names.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/message_instance.h>

#include "radar_ndt/io/imu_sample.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/io/vehicle_signals.h"
#include "radar_ndt/ros/mounting_tree.h"
#include "radar_ndt/ros/nuscenes_bag.h"

namespace radar_ndt {
namespace ros1 {
namespace detail {

constexpr const char* kCloud = "sensor_msgs/PointCloud2";
constexpr const char* kCloud1 = "sensor_msgs/PointCloud";  ///< the first point-cloud message (NTU4DRadLM's Eagle)
constexpr const char* kImage = "sensor_msgs/Image";
constexpr const char* kImu = "sensor_msgs/Imu";
constexpr const char* kOdometry = "nav_msgs/Odometry";
constexpr const char* kPoseStamped = "geometry_msgs/PoseStamped";
constexpr const char* kTf = "tf2_msgs/TFMessage";
constexpr const char* kTwistStamped = "geometry_msgs/TwistStamped";

/// Opens `path` for writing (replaced), its chunks compressed as asked (the writers').
void openForWriting(rosbag::Bag& bag, const std::string& path, BagCompression compression);

/// A pose as the nav_msgs/Odometry the bag writers put on /gt: `pose` of `child` in `parent`.
nav_msgs::Odometry odometryMessage(const Eigen::Isometry3d& pose, const ros::Time& stamp, const std::string& parent,
                                   const std::string& child);

/// "12.345678 s", for messages.
std::string seconds(const ros::Time& t);

/// A position and quaternion as an isometry, as the nuScenes tables are read (quaternion
/// normalised; one far from unit norm is refused), so that a bag written from a scene gives the
/// scene's transforms to the last bit.
Eigen::Isometry3d toIsometry(double x, double y, double z, double qw, double qx, double qy, double qz,
                             const std::string& what);

/// Problems of one kind said at most a few times, then counted.
class ProblemLog {
 public:
  void add(const std::string& key, const std::string& text);
  std::vector<std::string> finish();

 private:
  std::map<std::string, std::size_t> count_;
  std::vector<std::string> lines_;
};

/// An open bag and its topics' message types.
struct OpenBag {
  std::string path;
  std::unique_ptr<rosbag::Bag> bag;
  std::map<std::string, std::string> types;  ///< topic → message type
  /// Opens `path`: IoError for no such file, not a bag, cut off or unindexed (saying to run
  /// `rosbag reindex`).
  explicit OpenBag(const std::string& path);
  /// IoError unless `topic` is in the bag with one of `types` (`key` names it: "radar front").
  void expectType(const std::string& description, const std::string& key, const std::string& topic,
                  const std::set<std::string>& wanted) const;
  std::string topicList() const;
};

/// A message's time as the description says: its header stamp, or the bag's receive time (for a
/// driver that writes zero stamps, said once a topic).
class StampRule {
 public:
  explicit StampRule(StampSource source) : source_(source) {}
  ros::Time operator()(const ros::Time& header, const rosbag::MessageInstance& m, std::vector<std::string>& problems);

 private:
  StampSource source_;
  std::set<std::string> zero_stamps_;
};

/// The IMU, ground truth and base-frame transforms a description names, collected message by
/// message and finished into the vehicle's yaw rate and the ground-truth poses.
class MotionTopics {
 public:
  MotionTopics(const SensorDescription& d, const std::string& bag_path) : d_(d), path_(bag_path) {}
  /// The types of the IMU and ground truth topics (IoError otherwise).
  void check(const OpenBag& bag) const;
  /// The topics to read beside the radars': the IMU, the ground truth, /tf and /tf_static when there.
  std::vector<std::string> topics(const OpenBag& bag) const;
  /// Takes `m` when it is one of them; false otherwise.
  bool take(const rosbag::MessageInstance& m, StampRule& stamps, std::vector<std::string>& problems);
  /// The mounting of `frame`: from it into the base frame, through /tf_static and /tf as tf2
  /// resolves a chain of frames (MountingTree); nullopt, `why` saying what is missing, when none.
  std::optional<Eigen::Isometry3d> mounting(const std::string& frame, std::string* why) const {
    return tree_.lookup(d_.base_frame, frame, why);
  }
  /// The yaw rate and the speed (null without an IMU or speed topic; IoError when a named one has
  /// no finite value), the ground truth in time order, and what was met.
  void finish(std::shared_ptr<const VehicleSignals>& signals, Trajectory& ground_truth,
              std::vector<std::string>& problems);
  std::size_t imuMessages() const { return imu_messages_; }
  /// The IMU's messages with a finite gyro and accelerometer, turned into the base frame's axes
  /// (imu_mounting), at the description's stamps; moved out.
  std::vector<ImuSample> takeImuSamples() { return std::move(imu6_); }
  ProblemLog& log() { return log_; }

 private:
  void takeTf(const rosbag::MessageInstance& m);
  void takePose(const rosbag::MessageInstance& m, StampRule& stamps, std::vector<std::string>& problems);

  const SensorDescription& d_;
  std::string path_;
  MountingTree tree_;
  std::vector<std::pair<std::int64_t, double>> imu_, speed_;
  std::vector<ImuSample> imu6_;
  std::vector<std::pair<std::int64_t, Eigen::Isometry3d>> poses_;
  std::size_t imu_dropped_ = 0, imu_messages_ = 0, speed_dropped_ = 0;
  Eigen::Vector3d gravity_sum_ = Eigen::Vector3d::Zero();  ///< the first messages' specific force, base frame
  std::size_t gravity_count_ = 0;
  ProblemLog log_;
};

}  // namespace detail
}  // namespace ros1
}  // namespace radar_ndt

#include "radar_ndt/ros/nuscenes_bag.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>

#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include "bag_reading.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/nuscenes_can_bus.h"
#include "radar_ndt/ros/point_cloud2.h"
#include "radar_ndt/ros/ros_time.h"

namespace radar_ndt {
namespace ros1 {

namespace {

namespace fs = std::filesystem;

std::uint8_t datatypeOf(char type, std::size_t size, const std::string& path, const std::string& name) {
  using F = sensor_msgs::PointField;
  if (type == 'F' && size == 4) return F::FLOAT32;
  if (type == 'F' && size == 8) return F::FLOAT64;
  if (type == 'I' && size == 1) return F::INT8;
  if (type == 'I' && size == 2) return F::INT16;
  if (type == 'I' && size == 4) return F::INT32;
  if (type == 'U' && size == 1) return F::UINT8;
  if (type == 'U' && size == 2) return F::UINT16;
  if (type == 'U' && size == 4) return F::UINT32;
  throw IoError(path, "field '" + name + "': PCD type " + std::string(1, type) + std::to_string(size) +
                          " has no PointCloud2 datatype");
}

/// The PCD's fields as a PointCloud2, packed in the file's field order, little-endian.
sensor_msgs::PointCloud2 toCloud(const PcdTable& t, const std::string& path) {
  std::vector<std::uint8_t> types;
  for (std::size_t c = 0; c < t.names.size(); ++c)
    types.push_back(datatypeOf(t.types[c], t.sizes[c], path, t.names[c]));
  return writeCloud(t.names, types, t.points,
                    [&t](std::size_t i, std::size_t c) { return t.values[i * t.names.size() + c]; });
}

/// A transform with the tables' own quaternion (w x y z), so a reader normalising it as the
/// nuScenes reader does gets the same rotation to the last bit.
geometry_msgs::TransformStamped transformOf(const Eigen::Isometry3d& T, const Eigen::Vector4d& wxyz,
                                            const std::string& parent, const std::string& child,
                                            const ros::Time& stamp) {
  geometry_msgs::TransformStamped t;
  t.header.frame_id = parent;
  t.header.stamp = stamp;
  t.child_frame_id = child;
  t.transform.translation.x = T.translation().x();
  t.transform.translation.y = T.translation().y();
  t.transform.translation.z = T.translation().z();
  t.transform.rotation.w = wxyz[0];
  t.transform.rotation.x = wxyz[1];
  t.transform.rotation.y = wxyz[2];
  t.transform.rotation.z = wxyz[3];
  return t;
}

/// The CAN bus's ms_imu messages as sensor_msgs/Imu on /imu (nuscenes2bag's can.py get_imu_msg).
std::size_t writeImu(rosbag::Bag& bag, const NuScenesDataset& dataset, const NuScenesScene& scene) {
  const auto messages = readNuScenesImuMessages(dataset.dataroot(), scene.name);
  if (!messages) return 0;
  for (const CanImuMessage& m : *messages) {
    sensor_msgs::Imu imu;
    imu.header.stamp = rosTime(m.utime);
    imu.header.frame_id = "base_link";
    imu.angular_velocity.x = m.rotation_rate.x();
    imu.angular_velocity.y = m.rotation_rate.y();
    imu.angular_velocity.z = m.rotation_rate.z();
    imu.linear_acceleration.x = m.linear_accel.x();
    imu.linear_acceleration.y = m.linear_accel.y();
    imu.linear_acceleration.z = m.linear_accel.z();
    imu.orientation.w = m.q[0];
    imu.orientation.x = m.q[1];
    imu.orientation.y = m.q[2];
    imu.orientation.z = m.q[3];
    bag.write("/imu", imu.header.stamp, imu);
  }
  return messages->size();
}

}  // namespace

BagCompression parseBagCompression(const std::string& text) {
  if (text == "none") return BagCompression::None;
  if (text == "bz2") return BagCompression::Bz2;
  if (text == "lz4") return BagCompression::Lz4;
  throw std::invalid_argument("--compression must be none, bz2 or lz4, not '" + text + "'");
}

NuScenesBagStats writeNuScenesBag(const NuScenesDataset& dataset, const NuScenesScene& scene, const std::string& path,
                                  BagCompression compression) {
  NuScenesBagStats stats;
  rosbag::Bag bag;
  try {
    detail::openForWriting(bag, path, compression);
    for (const NuScenesSweep& s : dataset.radarSweeps(scene)) {
      const ros::Time stamp = rosTime(s.timestamp_us);
      tf2_msgs::TFMessage tf;
      tf.transforms.push_back(transformOf(s.ego_to_global, s.ego_rotation_wxyz, "map", "base_link", stamp));
      tf.transforms.push_back(transformOf(s.sensor_to_ego, s.sensor_rotation_wxyz, "base_link", s.channel, stamp));
      bag.write("/tf", stamp, tf);
      ++stats.tf_messages;
      sensor_msgs::PointCloud2 cloud = toCloud(readPcdTable(s.path), s.path);
      cloud.header.stamp = stamp;
      cloud.header.frame_id = s.channel;
      bag.write("/" + s.channel, stamp, cloud);
      ++stats.radar_messages;
    }
    stats.imu_messages = writeImu(bag, dataset, scene);
    bag.close();
  } catch (const rosbag::BagException& e) {
    throw IoError(path, std::string("cannot write the bag: ") + e.what());
  }
  return stats;
}

}  // namespace ros1
}  // namespace radar_ndt

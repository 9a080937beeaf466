#include "radar_ndt/ros/radar_4d_bag.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud.h>
#include <sensor_msgs/PointCloud2.h>

#include "bag_reading.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/ros/point_cloud2.h"
#include "radar_ndt/ros/ros_time.h"

namespace radar_ndt {
namespace ros1 {

namespace {

ros::Time stampOf(double t, const std::string& path) {
  if (!(t >= 0) || !std::isfinite(t))
    throw IoError(path, "a time of " + std::to_string(t) + " s cannot be a ROS time (seconds since 1970)");
  return rosTime(static_cast<std::int64_t>(std::llround(t * 1e6)));
}

sensor_msgs::PointField field(const std::string& name, std::uint32_t offset) {
  sensor_msgs::PointField f;
  f.name = name;
  f.offset = offset;
  f.datatype = sensor_msgs::PointField::FLOAT32;
  f.count = 1;
  return f;
}

/// ti_mmwave_rospkg's cloud: pcl::PointXYZI's padded layout with the velocity after the intensity.
sensor_msgs::PointCloud2 tiCloud(const pcl::PointCloud<PointRadar4D>& scan, double sign) {
  sensor_msgs::PointCloud2 c;
  c.height = 1;
  c.width = static_cast<std::uint32_t>(scan.size());
  c.fields = {field("x", 0), field("y", 4), field("z", 8), field("intensity", 16), field("velocity", 20)};
  c.is_bigendian = false;
  c.point_step = 32;
  c.row_step = c.point_step * c.width;
  c.is_dense = true;
  c.data.assign(c.row_step, 0);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const PointRadar4D& p = scan[i];
    const float values[5] = {p.x, p.y, p.z, p.power, static_cast<float>(sign * p.doppler)};
    const std::uint32_t offsets[5] = {0, 4, 8, 16, 20};
    for (int k = 0; k < 5; ++k) std::memcpy(&c.data[i * c.point_step + offsets[k]], &values[k], sizeof(float));
  }
  return c;
}

sensor_msgs::PointCloud2 snailCloud(const pcl::PointCloud<PointRadar4D>& scan, double sign) {
  using F = sensor_msgs::PointField;
  return writeCloud({"x", "y", "z", "doppler", "intensity"},
                    {F::FLOAT32, F::FLOAT32, F::FLOAT32, F::FLOAT32, F::FLOAT32}, scan.size(),
                    [&](std::size_t i, std::size_t k) -> double {
                      const PointRadar4D& p = scan[i];
                      switch (k) {
                        case 0: return p.x;
                        case 1: return p.y;
                        case 2: return p.z;
                        case 3: return sign * p.doppler;
                        default: return p.rcs;
                      }
                    });
}

sensor_msgs::PointCloud eagleCloud(const pcl::PointCloud<PointRadar4D>& scan, double sign) {
  sensor_msgs::PointCloud c;
  c.channels.resize(3);
  c.channels[0].name = "Doppler";
  c.channels[1].name = "Range";
  c.channels[2].name = "Power";
  for (const PointRadar4D& p : scan) {
    geometry_msgs::Point32 q;
    q.x = p.x;
    q.y = p.y;
    q.z = p.z;
    c.points.push_back(q);
    c.channels[0].values.push_back(static_cast<float>(sign * p.doppler));
    c.channels[1].values.push_back(std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z));
    c.channels[2].values.push_back(p.power);
  }
  return c;
}

/// The IMU's readings turned into its described axes, on the description's IMU topic.
std::size_t writeImu(rosbag::Bag& bag, const SensorDescription& d, const Radar4DRecording& r, const std::string& path) {
  const Eigen::Matrix3d imu_axes = imuRotation(d).transpose();  // base frame's axes into the IMU's
  for (const ImuSample& s : r.imu) {
    sensor_msgs::Imu m;
    m.header.stamp = stampOf(s.t, path);
    m.header.frame_id = "imu";
    m.orientation_covariance[0] = -1;  // no orientation (REP 145)
    const Eigen::Vector3d w = imu_axes * s.gyro, a = imu_axes * s.accel;
    m.angular_velocity.x = w.x();
    m.angular_velocity.y = w.y();
    m.angular_velocity.z = w.z();
    m.linear_acceleration.x = a.x();
    m.linear_acceleration.y = a.y();
    m.linear_acceleration.z = a.z();
    bag.write(d.imu_topic, m.header.stamp, m);
  }
  return r.imu.size();
}

/// The base frame's poses as nav_msgs/Odometry on the description's ground-truth topic (or /gt).
std::size_t writeGroundTruth(rosbag::Bag& bag, const SensorDescription& d, const Trajectory& truth,
                             const std::string& path) {
  const std::string topic = d.ground_truth_topic.empty() ? "/gt" : d.ground_truth_topic;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const nav_msgs::Odometry o = detail::odometryMessage(truth.poses[i], stampOf(truth.stamps[i], path),
                                                         d.ground_truth_parent, d.ground_truth_child);
    bag.write(topic, o.header.stamp, o);
  }
  return truth.size();
}

}  // namespace

Radar4DBagStats writeRadar4DBag(const std::string& path, Radar4DBagLayout layout, const SensorDescription& d,
                                const Radar4DRecording& r, BagCompression compression) {
  if (r.stamps.size() != r.scans.size())
    throw std::invalid_argument(std::to_string(r.stamps.size()) + " stamps for " + std::to_string(r.scans.size()) +
                                " scans");
  if (d.radars.empty()) throw IoError(d.source, "the description names no radar to write");
  const RadarDescription& radar = d.radars.front();
  if (radar.fields.doppler != DopplerKind::Radial)
    throw IoError(d.source, "a 4D radar's bag is written for a radial Doppler field");
  // The value written is what the description turns back into "positive receding".
  const double sign = radar.fields.radial_sign;
  Radar4DBagStats stats;
  rosbag::Bag bag;
  try {
    detail::openForWriting(bag, path, compression);
    for (std::size_t k = 0; k < r.scans.size(); ++k) {
      const ros::Time t = stampOf(r.stamps[k], path);
      if (layout == Radar4DBagLayout::TiMmwave) {
        bag.write(radar.topic, t, tiCloud(r.scans[k], sign));  // the driver's zero stamp, no frame id
      } else if (layout == Radar4DBagLayout::SnailArs548) {
        sensor_msgs::PointCloud2 c = snailCloud(r.scans[k], sign);
        c.header.stamp = t;
        c.header.frame_id = "ars548";
        bag.write(radar.topic, t, c);
      } else {
        sensor_msgs::PointCloud c = eagleCloud(r.scans[k], sign);
        c.header.stamp = t;
        c.header.frame_id = "eagle";
        bag.write(radar.topic, t, c);
      }
      ++stats.scans;
    }
    if (!d.imu_topic.empty()) stats.imu = writeImu(bag, d, r, path);
    stats.ground_truth = writeGroundTruth(bag, d, r.truth, path);
    bag.close();
  } catch (const rosbag::BagException& e) {
    throw IoError(path, std::string("cannot write the bag: ") + e.what());
  }
  return stats;
}

}  // namespace ros1
}  // namespace radar_ndt

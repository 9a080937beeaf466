#include "radar_ndt/ros/scan_bag.h"

#include <algorithm>

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>

#include "bag_reading.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/ros/ros_time.h"

namespace radar_ndt {
namespace ros1 {

ScanBagStats writeScanBag(const ScanningSequence& sequence, const std::string& path, BagCompression compression) {
  ScanBagStats stats;
  rosbag::Bag bag;
  try {
    detail::openForWriting(bag, path, compression);
    for (std::size_t k = 0; k < sequence.size(); ++k) {
      PolarScan scan;
      try {
        scan = sequence.load(k);
      } catch (const IoError&) {
        ++stats.unreadable;
        continue;
      }
      sensor_msgs::Image image;
      image.header.stamp = rosTime(scan.stamp);
      image.header.frame_id = "navtech";
      image.height = static_cast<std::uint32_t>(scan.azimuths);
      image.width = static_cast<std::uint32_t>(scan.bins);
      image.encoding = "mono8";
      image.is_bigendian = 0;
      image.step = image.width;
      image.data = scan.power;
      bag.write("/Navtech/Polar", image.header.stamp, image);
      ++stats.scans;
    }
    const Trajectory& gt = sequence.groundTruth();
    for (std::size_t i = 0; i < gt.size(); ++i) {
      const nav_msgs::Odometry o = detail::odometryMessage(
          gt.poses[i], rosTime(static_cast<std::int64_t>(std::llround(gt.stamps[i] * 1e6))), "world", "navtech");
      bag.write("/gt", o.header.stamp, o);
      ++stats.ground_truth;
    }
    if (const std::optional<VehicleSignals> imu = sequence.gyro(nullptr)) {
      for (std::size_t i = 0; i < imu->yaw_rate.size(); ++i) {
        sensor_msgs::Imu m;
        m.header.stamp = rosTime(imu->yaw_rate.stamps_us[i]);
        m.header.frame_id = "navtech";
        m.orientation_covariance[0] = -1;  // no orientation (REP 145)
        m.angular_velocity.z = imu->yaw_rate.values[i];
        bag.write("/imu", m.header.stamp, m);
        ++stats.imu;
      }
    }
    bag.close();
  } catch (const rosbag::BagException& e) {
    throw IoError(path, std::string("cannot write the bag: ") + e.what());
  }
  return stats;
}

}  // namespace ros1
}  // namespace radar_ndt

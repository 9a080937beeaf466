#pragma once
// A scanning-radar sequence (Oxford, Boreas, RADIATE) written as a ROS 1 bag in the layout CFEAR's
// bags of Oxford have (dan11003/CFEAR_Radarodometry_code_public, radar_driver.cpp): one
// sensor_msgs/Image a sweep on /Navtech/Polar, 8 bits a bin (mono8), a row an azimuth and a column
// a range bin (the power bins only: the dataset's per-row metadata has no place in it), stamped
// with the scan's time, frame_id `navtech`; the sequence's ground truth as nav_msgs/Odometry on
// /gt (world -> navtech); Boreas' gyro as sensor_msgs/Imu on /imu. `preset:navtech_oxford` and
// `preset:navtech_boreas` read them.

#include <string>

#include "radar_ndt/io/scanning_sequence.h"
#include "radar_ndt/ros/nuscenes_bag.h"

namespace radar_ndt {
namespace ros1 {

struct ScanBagStats {
  std::size_t scans = 0, unreadable = 0, ground_truth = 0, imu = 0;
};

/// Writes `sequence` to `path` (replaced); a scan that cannot be read is left out and counted.
/// Throws IoError naming the file that could not be written.
ScanBagStats writeScanBag(const ScanningSequence& sequence, const std::string& path,
                          BagCompression compression = BagCompression::None);

}  // namespace ros1
}  // namespace radar_ndt

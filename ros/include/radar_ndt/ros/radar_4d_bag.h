#pragma once
// A 4D radar recording (scans, a 6-axis IMU, ground truth) written as a ROS 1 bag in the layout
// of a real driver's messages, so that a simulated sequence is read exactly as a user's recording
// of that radar is (radar_sim --type 4d; docs/simulator.md):
//   - TiMmwave: ti_mmwave_rospkg 3.3.0 as christopherdoer/rio's bag holds it: sensor_msgs/PointCloud2
//     with x y z (0, 4, 8) intensity (16) velocity (20) float32 in a 32-byte point, header stamp
//     zero and frame id empty (the driver's), the message's time the bag's receive time.
//   - SnailArs548: Snail-Radar's /ars548 (its _data/ars548.csv): PointCloud2 with x y z doppler
//     intensity (RCS, dB m²) float32, stamped, frame id "ars548".
//   - NtuEagle: NTU4DRadLM's Oculii Eagle (as 4DRadarSLAM reads it): sensor_msgs/PointCloud with
//     the channels Doppler, Range, Power, stamped, frame id "eagle".
// The topics and the Doppler's sign come from the sensor description the bag is to be read with;
// the IMU's readings are turned into its described axes (`imu_mounting`); the ground truth is
// nav_msgs/Odometry on `ground_truth_topic` (or /gt).

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <pcl/point_cloud.h>

#include "radar_ndt/io/imu_sample.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/point_types.h"
#include "radar_ndt/ros/nuscenes_bag.h"

namespace radar_ndt {
namespace ros1 {

enum class Radar4DBagLayout { TiMmwave, SnailArs548, NtuEagle };

/// What is written: scans in the radar's frame (doppler positive receding, power the driver's
/// intensity or power, rcs in dB m²), the IMU's readings in the base frame's axes, the base
/// frame's poses in the world.
struct Radar4DRecording {
  std::vector<double> stamps;  ///< s, one a scan
  std::vector<pcl::PointCloud<PointRadar4D>> scans;
  std::vector<ImuSample> imu;
  Trajectory truth;
};

struct Radar4DBagStats {
  std::size_t scans = 0, imu = 0, ground_truth = 0;
};

/// Writes `recording` to `path` (replaced) in `layout`, with the topics and Doppler sign of the
/// first radar of `description`. Throws IoError naming the file (a time before 1970, a bag that
/// cannot be written) and std::invalid_argument for stamps and scans that disagree in number.
Radar4DBagStats writeRadar4DBag(const std::string& path, Radar4DBagLayout layout, const SensorDescription& description,
                                const Radar4DRecording& recording, BagCompression compression = BagCompression::None);

}  // namespace ros1
}  // namespace radar_ndt

#pragma once
// A nuScenes scene written as a ROS 1 bag in nuscenes2bag's layout (foxglove/nuscenes2bag): one
// sensor_msgs/PointCloud2 topic a radar (/RADAR_FRONT, ...) carrying the PCD's fields as they are
// (names, types, values), frame_id the channel and stamp the sweep's; /tf with map -> base_link
// (the ego pose) and base_link -> channel (the calibration) at every sweep; /imu
// (sensor_msgs/Imu) from the CAN bus's ms_imu when the dataroot has can_bus/. Cameras, lidar,
// annotations and the CAN bus's other messages are not written. `preset:nuscenes_ars408` reads it.

#include <string>

#include "radar_ndt/io/nuscenes.h"

namespace radar_ndt {
namespace ros1 {

enum class BagCompression { None, Bz2, Lz4 };
/// "none" | "bz2" | "lz4" (the apps' --compression); std::invalid_argument naming another.
BagCompression parseBagCompression(const std::string& text);

struct NuScenesBagStats {
  std::size_t radar_messages = 0, tf_messages = 0, imu_messages = 0;
};

/// Writes `scene` to `path` (replaced). Throws IoError naming the file that could not be read or written.
NuScenesBagStats writeNuScenesBag(const NuScenesDataset& dataset, const NuScenesScene& scene, const std::string& path,
                                  BagCompression compression = BagCompression::None);

}  // namespace ros1
}  // namespace radar_ndt

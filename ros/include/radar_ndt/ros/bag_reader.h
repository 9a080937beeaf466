#pragma once
// ROS 1 bags as recordings (radar_ndt/io/recording.h): registers the reader of the format
// "rosbag", which reads a bag as a sensor description says (point-cloud radars:
// RosbagRadarSequence with the car's signals; one scanning radar: RosbagScanSequence). Apps, the
// Python module and tests that read bags call it once.

namespace radar_ndt {
namespace ros1 {

void registerBagReader();

}  // namespace ros1
}  // namespace radar_ndt

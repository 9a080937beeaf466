#include "radar_ndt/ros/bag_reader.h"

#include "radar_ndt/io/recording.h"
#include "radar_ndt/ros/rosbag_scans.h"
#include "radar_ndt/ros/rosbag_sequence.h"

namespace radar_ndt {
namespace ros1 {

void registerBagReader() {
  registerRecordingReader("rosbag", [](const std::string& path, const SensorDescription& d) {
    Recording r;
    if (!d.radars.empty() && d.radars[0].kind == RadarKind::Scanning) {
      r.scans = std::make_unique<const RosbagScanSequence>(path, d);
      return r;
    }
    auto bag = std::make_unique<const RosbagRadarSequence>(path, d);
    r.car = bag->vehicleSignals();
    r.problems = bag->problems();
    r.imu = bag->imuSamples();
    r.cycles = std::move(bag);
    return r;
  });
}

}  // namespace ros1
}  // namespace radar_ndt

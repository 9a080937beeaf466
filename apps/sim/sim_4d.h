#pragma once
// radar_sim --type 4d: a 4D radar (x, y, z, Doppler, power) and a 6-axis IMU along a 6-DoF motion
// (a TUM pose file, a Boreas applanix/*_poses.csv, or a built-in hand-held walk or car drive),
// written as a folder: the scans as a ROS 1 bag in the layout of the radar's real driver
// (ros/radar_4d_bag.h) with the sensor description that reads it, the truth as TUM, the scans
// as PCD files. `radar_odometry --format rosbag --bag DIR/radar.bag --sensors DIR/sensors.yaml`
// reads it.

#include <cstddef>
#include <cstdint>
#include <string>

namespace radar_ndt {
namespace apps {

struct Sim4DRequest {
  std::string preset = "ti_iwr6843_rio";  ///< the radar model (sim/radar_4d.h)
  std::string sensors;                    ///< the description the bag follows; empty: the preset's
  std::string trajectory;                 ///< TUM or Boreas poses; empty: the built-in motion
  std::string imu = "mems";               ///< none | mems | navigation
  std::string out;
  double rate = 0;         ///< scans a second; 0: the preset's
  std::size_t frames = 0;  ///< scans at most; 0: the whole trajectory
  std::uint64_t seed = 1;
};

/// The sensor description preset the preset's driver layout is read with: ti_iwr6843_rio,
/// snail_radar_ars548, ntu4dradlm_eagle.
std::string sensorPresetFor(const std::string& radar_preset);

/// Simulates and writes; prints what was written. std::invalid_argument or IoError on bad input.
void writeSequence4D(const Sim4DRequest& request);

}  // namespace apps
}  // namespace radar_ndt

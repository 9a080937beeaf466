#pragma once
// The nuScenes CAN bus expansion as its devkit reads it (NuScenesCanBus): one JSON file per scene
// and message, <dataroot>/can_bus/<scene>_<message>.json, each a list of messages with `utime` (µs,
// on the sweeps' clock). What the pipelines use of it, as time series they query by interval:
//  - ms_imu (100 Hz): `rotation_rate` [x, y, z] rad/s in the IMU's frame (x forward, y left, z up):
//    the yaw rate is z;
//  - zoe_veh_info (100 Hz): `RL_wheel_speed`, `RR_wheel_speed` (rpm): the rear axle, where the
//    nuScenes ego frame sits, so their mean times 2π r / 60 is the ego frame's speed.
// Python's json module writes NaN and Infinity as bare words, which JSON has not: they are read as
// missing values, and a message whose value is missing is left out (counted).

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "radar_ndt/io/vehicle_signals.h"
#include "radar_ndt/time_series.h"

namespace radar_ndt {

/// The CAN bus of `scene_name` under `dataroot`: nothing when `dataroot`/can_bus is not there (the
/// run goes on without it; the caller says so). Throws IoError naming the file when the folder is
/// there but a message file is missing, is not a JSON list of objects, or a message lacks `utime`
/// or a value, holds a value of the wrong type, or runs back in time.
std::optional<VehicleSignals> readNuScenesCanBus(const std::string& dataroot, const std::string& scene_name);

/// One message file's series: the mean of `keys`' values (each a number, or element `index` of
/// an array of numbers) against `utime`, the file parsed once. A message with any of them missing
/// (NaN) is left out; messages with equal `utime` keep the first. Throws IoError as above.
TimeSeries readCanBusSeries(const std::string& file, const std::vector<std::string>& keys, int index = -1,
                            std::size_t* dropped = nullptr);

/// One ms_imu message as the devkit's files hold it.
struct CanImuMessage {
  std::int64_t utime = 0;
  Eigen::Vector3d rotation_rate = Eigen::Vector3d::Zero();  ///< rad/s, x forward, y left, z up
  Eigen::Vector3d linear_accel = Eigen::Vector3d::Zero();   ///< m/s², gravity included
  std::array<double, 4> q{1, 0, 0, 0};                      ///< w, x, y, z: attitude, arbitrary yaw
};
/// One zoe_veh_info message: the four wheel speeds (rpm).
struct CanWheelMessage {
  std::int64_t utime = 0;
  double fl = 0, fr = 0, rl = 0, rr = 0;
};

/// The scene's ms_imu messages as the file holds them (NaN where it has NaN or null); nullopt when
/// the dataroot has no can_bus/ folder. Throws IoError for a file that is missing or malformed.
std::optional<std::vector<CanImuMessage>> readNuScenesImuMessages(const std::string& dataroot,
                                                                  const std::string& scene_name);

/// Writes <dataroot>/can_bus/<scene>_ms_imu.json and <scene>_zoe_veh_info.json (the folder
/// created), the fields readNuScenesCanBus and the devkit read, atomically.
void writeNuScenesCanBus(const std::string& dataroot, const std::string& scene_name,
                         const std::vector<CanImuMessage>& imu, const std::vector<CanWheelMessage>& wheels);

}  // namespace radar_ndt

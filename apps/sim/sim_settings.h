#pragma once
// radar_sim's settings: every number of the simulator's world, scanning sensor, automotive
// sensor, gyro and wheel speeds, by name (`--set name=value`, `--list-settings`), read from their
// field tables (radar_ndt/sim/radar_sim.h). A name two tables share is given a distinct one there.

#include <string>
#include <vector>

#include "radar_ndt/sim/radar_sim.h"

namespace radar_ndt {
namespace apps {

/// What the settings change.
struct SimConfig {
  sim::WorldOptions world;
  sim::ScanningOptions scanning;
  sim::AutomotiveOptions automotive;
  sim::ImuOptions imu;       ///< the gyro's errors (--imu picks a preset)
  sim::WheelOptions wheels;  ///< the wheel speeds' (automotive, with --imu)
};

/// Sets `assignment` ("name=value") on `config`; std::invalid_argument naming the setting or the
/// value that is wrong.
void applySetting(const std::string& assignment, SimConfig& config);

/// Every setting, grouped (world, scanning, automotive): "  name  value  help" lines.
std::string listSettings(const SimConfig& config);

/// Every setting as one markdown table, its value in each of `columns` (a profile's name and its
/// settings) side by side (radar_sim --list-settings --markdown; docs/simulator.md holds it).
std::string settingsMarkdown(const std::vector<std::pair<std::string, SimConfig>>& columns);

}  // namespace apps
}  // namespace radar_ndt

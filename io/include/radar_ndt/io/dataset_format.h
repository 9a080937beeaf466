#pragma once
// The formats a run reads, with one name table (radar_ndt/fields.h): how the command line, Python,
// radar_batch and the run entry spell them, parse them and list them.

#include <stdexcept>

#include "radar_ndt/fields.h"
#include "radar_ndt/io/scanning_sequence.h"

namespace radar_ndt {

enum class DatasetFormat { NuScenes, Rosbag, Oxford, Radiate, Boreas };
template <>
struct EnumNames<DatasetFormat> {
  static constexpr const char* what = "format";
  static constexpr EnumName<DatasetFormat> names[] = {
      {DatasetFormat::NuScenes, "nuscenes", "a nuScenes dataroot (automotive)"},
      {DatasetFormat::Rosbag, "rosbag", "a ROS 1 bag through a sensor description (either pipeline)"},
      {DatasetFormat::Oxford, "oxford", "an Oxford Radar RobotCar sequence folder (scanning)"},
      {DatasetFormat::Radiate, "radiate", "a RADIATE sequence folder (scanning)"},
      {DatasetFormat::Boreas, "boreas", "a Boreas sequence folder (scanning)"}};
};

/// Whether `f` is a scanning radar's sequence folder (oxford, radiate, boreas).
inline bool isScanLayout(DatasetFormat f) {
  return f == DatasetFormat::Oxford || f == DatasetFormat::Radiate || f == DatasetFormat::Boreas;
}

/// The layout of a scanning radar's sequence folder; std::invalid_argument for the others.
inline ScanFormat scanFormatOf(DatasetFormat f) {
  switch (f) {
    case DatasetFormat::Oxford: return ScanFormat::Oxford;
    case DatasetFormat::Radiate: return ScanFormat::Radiate;
    case DatasetFormat::Boreas: return ScanFormat::Boreas;
    default: throw std::invalid_argument(std::string(toString(f)) + " is not a scanning radar's sequence folder");
  }
}

}  // namespace radar_ndt

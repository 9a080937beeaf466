#pragma once
// A sensor_msgs/PointCloud2's fields (or a sensor_msgs/PointCloud's channels) read by name, as the
// table of doubles the radar point conversion takes (radar_ndt/io/radar_point_fields.h): any field
// order, offsets and datatype, either byte order, organised or not. A malformed message is an
// error saying what is wrong. And the one writer of clouds (a nuScenes scene's bag, the node's maps).

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <sensor_msgs/PointCloud.h>
#include <sensor_msgs/PointCloud2.h>

namespace radar_ndt {
namespace ros1 {

struct CloudColumns {
  std::size_t points = 0;
  std::vector<double> table;  ///< row-major: one row a point, one column a requested field
  std::vector<char> present;  ///< per requested field: whether the message has it
};

/// Reads the fields `names` of every point (NaN where a field is absent). Throws
/// std::invalid_argument naming the problem: a data size that disagrees with width, height and
/// point_step, a field beyond the point, an unknown datatype.
CloudColumns readCloudColumns(const sensor_msgs::PointCloud2& cloud, const std::vector<std::string>& names);

/// "x, y, z, intensity": the message's field names, for messages.
std::string fieldNames(const sensor_msgs::PointCloud2& cloud);

/// The same table from a sensor_msgs/PointCloud (the first point-cloud message, which some 4D radar
/// drivers still publish: NTU4DRadLM's Oculii Eagle): "x", "y" and "z" are the points', every other
/// name a channel's; a name "#N" is the N-th channel whatever it is called (for drivers whose
/// readers address channels by position). Throws std::invalid_argument when a channel's values are
/// not one per point.
CloudColumns readCloudColumns(const sensor_msgs::PointCloud& cloud, const std::vector<std::string>& names);

/// "x, y, z, Doppler, Power": the points' coordinates and the channels' names, for messages.
std::string fieldNames(const sensor_msgs::PointCloud& cloud);

/// A cloud of `points` points in one row, little-endian, its fields packed in order: field k named
/// names[k], of PointField datatype types[k], point i's value value(i, k) converted to it (as a
/// static_cast from double). std::invalid_argument for an unknown datatype.
sensor_msgs::PointCloud2 writeCloud(const std::vector<std::string>& names, const std::vector<std::uint8_t>& types,
                                    std::size_t points, const std::function<double(std::size_t, std::size_t)>& value);

}  // namespace ros1
}  // namespace radar_ndt

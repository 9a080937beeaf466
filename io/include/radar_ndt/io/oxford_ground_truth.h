#pragma once
// Oxford Radar RobotCar ground truth: `gt/radar_odometry.csv`, the motion between consecutive
// scans.

#include <cstdint>
#include <string>
#include <vector>

namespace radar_ndt {

/// One row of Oxford `gt/radar_odometry.csv`: the motion from the destination scan (the earlier)
/// to the source scan (the later), i.e. the source scan's pose in the destination scan's frame,
/// x y z roll pitch yaw in Oxford's sensor axes (x forward, y right, z down).
struct OxfordRelativePose {
  std::int64_t source = 0;       ///< source_timestamp (later scan)
  std::int64_t destination = 0;  ///< destination_timestamp (earlier scan)
  double x = 0, y = 0, z = 0, roll = 0, pitch = 0, yaw = 0;
  std::int64_t source_radar = 0;
  std::int64_t destination_radar = 0;
};
/// Reads the CSV by its header's column names (the dataset's order:
/// source_timestamp,destination_timestamp,x,y,z,roll,pitch,yaw,source_radar_timestamp,
/// destination_radar_timestamp; the last two optional). Rows must chain in time.
std::vector<OxfordRelativePose> readOxfordRadarOdometry(const std::string& path);
void writeOxfordRadarOdometry(const std::string& path, const std::vector<OxfordRelativePose>& rows);

}  // namespace radar_ndt

#pragma once
// View-of-Delft (VoD, TU Delft): a ZF FRGen21 3+1D radar (about 13 Hz) behind a car's front
// bumper, in the layout its devkit reads (tudelft-iv/view-of-delft-dataset: docs/SENSORS_AND_DATA.md,
// vod/frame/data_loader.py and transformations.py):
//
//   <root>/radar/<split>/velodyne/NNNNN.bin   float32 rows: x y z RCS v_r v_r_compensated time
//   <root>/radar/<split>/calib/NNNNN.txt      KITTI calibration; its Tr_velo_to_cam (the 6th line)
//                                             is here the radar-to-camera transform T_camera_radar
//   <root>/radar/<split>/pose/NNNNN.json      three JSON lines: {"odomToCamera": [16]},
//                                             {"mapToCamera": [16]}, {"UTMToCamera": [16]}, each the
//                                             camera's pose in that world, row-major 4x4
//
// The radar frame: x forward, y left, z up. v_r is the radial velocity relative to the radar,
// positive receding (a static point ahead of a car driving forward reads negative; checked on the
// devkit's example frames: the static points' fit gives the car moving forward), and
// v_r_compensated = v_r plus the ego-motion's part, the target's own radial velocity. `time` is
// the scan a point comes from in the accumulated clouds (0 the frame's own scan, −1, −2 earlier).
// Frames carry no timestamps in this layout.

#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>

#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/point_types.h"

namespace radar_ndt {

/// The nominal period of VoD's radar (about 13 Hz): a point's time_offset is its `time` id times it.
constexpr double kVodRadarPeriod = 1.0 / 13.0;

/// One .bin: points in the radar frame (x, y, z; rcs = RCS; doppler = v_r, positive receding;
/// time_offset = time · kVodRadarPeriod; power 1, the paper's weight for automotive detections).
/// `compensated` (optional) gets v_r_compensated, one per point. Rows with a non-finite value are
/// left out and counted in `dropped` (optional). Throws IoError naming the file when it cannot be
/// read or its size is not a whole number of 7-float rows.
pcl::PointCloud<PointRadar4D> readVodRadarBin(const std::string& path, std::vector<float>* compensated = nullptr,
                                              std::size_t* dropped = nullptr);

/// Writes `cloud` as a VoD .bin (v_r_compensated from `compensated` when given, else v_r; time =
/// time_offset / kVodRadarPeriod rounded), atomically.
void writeVodRadarBin(const std::string& path, const pcl::PointCloud<PointRadar4D>& cloud,
                      const std::vector<float>* compensated = nullptr);

/// The camera's pose in one of the pose file's worlds: "odomToCamera" (default), "mapToCamera" or
/// "UTMToCamera". Throws IoError naming the file and the key when it is missing or not 16 finite
/// numbers of a rigid transform.
Eigen::Isometry3d readVodCameraPose(const std::string& path, const std::string& key = "odomToCamera");

/// T_camera_radar from a radar calibration file (its Tr_velo_to_cam line). Throws IoError naming
/// the file when the line is missing or malformed.
Eigen::Isometry3d readVodRadarToCamera(const std::string& path);

/// The frames of one split, sorted by number: every .bin under radar/<split>/velodyne.
class ViewOfDelftSequence {
 public:
  /// Throws IoError when the velodyne folder is missing or holds no .bin.
  explicit ViewOfDelftSequence(const std::string& root, const std::string& split = "training");
  std::size_t size() const { return ids_.size(); }
  const std::string& id(std::size_t k) const { return ids_.at(k); }
  std::string binPath(std::size_t k) const;
  std::string posePath(std::size_t k) const;
  std::string calibPath(std::size_t k) const;
  /// Frame k's points in the radar frame (readVodRadarBin).
  pcl::PointCloud<PointRadar4D> load(std::size_t k, std::vector<float>* compensated = nullptr) const;
  /// The radar's pose in the odom world: T_odom_camera · T_camera_radar.
  Eigen::Isometry3d radarPose(std::size_t k) const;
  /// The radar's poses in the odom world, frame by frame (no stamps: VoD's frames have none).
  /// Only meaningful over consecutive frames of one clip.
  Trajectory radarTrajectory() const;

 private:
  std::string dir_;
  std::vector<std::string> ids_;
};

}  // namespace radar_ndt

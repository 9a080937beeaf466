#pragma once
// nuScenes-layout radar datasets: the radar PCD files as nuScenes writes them and the JSON tables
// that say which sweep belongs to which scene, where each sensor is mounted and where the vehicle
// was. Nothing here is specific to a channel name: radar channels are whatever `sensor.json` lists
// with modality "radar".

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>

#include "radar_ndt/fields.h"
#include "radar_ndt/io/radar_point_fields.h"
#include "radar_ndt/point_types.h"

namespace radar_ndt {

/// ARS408 accuracy state index (the PCD fields x_rms, y_rms, vx_rms, vy_rms) to metres or m/s.
/// Index 31 ("invalid") and out-of-range indices give NaN.
double ars408RmsValue(int state_index);

/// Which detections the reader keeps: each list holds the values kept. Defaults: the paper's 150 m
/// range, the valid cluster states of the ARS408 (0 and the "valid with a remark" states), every
/// dynamic property, every Doppler ambiguity state (the devkit's default, made for object
/// detection, keeps ambig_state 3 alone: about a tenth of the valid detections fewer, and worse
/// odometry on the shared scenes: docs/results/nuscenes.md, "Which detections"). An empty list
/// accepts every value.
struct NuScenesRadarFilter {
  double max_range = 150.0;
  std::vector<int> invalid_states{0, 4, 8, 9, 10, 11, 12, 15, 16, 17};
  std::vector<int> dyn_props{};
  std::vector<int> ambig_states{};
  /// ambig_state values whose Doppler is used (the ego-velocity fit, the moving-detection test);
  /// the others are kept for the map and the match, their Doppler unused (RadarPointFields::keep_doppler).
  std::vector<int> doppler_ambig_states{};
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void NuScenesRadarFilter::fields(Visit&& visit) {
  using S = NuScenesRadarFilter;
  visit(&S::max_range,
        Field("max_range", "detections beyond this range dropped").unit("m").positive().cli("max-range"));
  visit(&S::invalid_states, Field("invalid_states", "invalid_state values kept (empty: all)"));
  visit(&S::dyn_props, Field("dyn_props", "dyn_prop values kept (empty: all)"));
  visit(&S::ambig_states,
        Field("ambig_states", "ambig_state values kept (empty: all; the nuScenes devkit's default: 3)")
            .cli("ambig-states"));
  visit(&S::doppler_ambig_states,
        Field("doppler_ambig_states",
              "ambig_state values whose Doppler the ego-velocity fit and the moving-detection test use; the "
              "others are kept for the map and the match alone (empty: every kept detection's)")
            .cli("doppler-ambig-states"));
}

struct NuScenesPcdStats {
  std::size_t points_in_file = 0;
  std::size_t kept = 0;
  std::size_t dropped_by_filter = 0;
  std::size_t dropped_non_finite = 0;  ///< NaN or Inf coordinates or velocities
};

/// The ARS408's fields as nuScenes writes them (x y z, vx vy, rcs, the x_rms y_rms accuracy
/// states) with `filter` as their keep lists: what readNuScenesRadarPcd converts with, and the
/// nuScenes sensor preset describes.
RadarPointFields nuScenesArs408Fields(const NuScenesRadarFilter& filter);

/// Reads one nuScenes radar PCD (DATA binary, ascii or binary_compressed; any field order; fields
/// it does not use are skipped) into PointRadar in the sensor frame: x y z, `doppler` = the radial
/// part of (vx, vy) (positive when the target recedes), `rcs`, `power` = 1, `sensor_id`, and the
/// reported accuracy as a diagonal sensor-frame covariance cov_xx = x_rms², cov_yy = y_rms² (0 when
/// the file has no valid rms). `vx_comp`/`vy_comp` are never read. Required fields: x y vx vy.
/// The header is checked against the file size before anything is allocated; `POINTS 0` gives an
/// empty cloud. Throws IoError naming the file and the problem.
pcl::PointCloud<PointRadar> readNuScenesRadarPcd(const std::string& path, const NuScenesRadarFilter& filter,
                                                 std::uint16_t sensor_id, NuScenesPcdStats* stats = nullptr);

/// Every field of a radar PCD as read, for writing it elsewhere (a ROS bag's PointCloud2) as it is.
struct PcdTable {
  std::vector<std::string> names;
  std::vector<char> types;         ///< the PCD's TYPE letter: 'F' float, 'I' signed, 'U' unsigned
  std::vector<std::size_t> sizes;  ///< bytes: 1, 2, 4 or 8
  std::size_t points = 0;
  std::vector<double> values;  ///< row-major: values[i * names.size() + c] (each field's first element)
};

/// Reads every field of a PCD file (ascii, binary or binary_compressed). Throws IoError.
PcdTable readPcdTable(const std::string& path);

struct NuScenesScene {
  std::string token;
  std::string name;
  std::string description;
  std::string log_token;
  std::int64_t first_timestamp_us = 0;
  std::int64_t last_timestamp_us = 0;
};

/// One radar sweep (a row of sample_data.json).
struct NuScenesSweep {
  std::string token;
  std::string channel;
  std::uint16_t channel_index = 0;  ///< index into NuScenesDataset::radarChannels()
  std::int64_t timestamp_us = 0;
  std::string path;  ///< dataroot + filename
  bool is_key_frame = false;
  Eigen::Isometry3d sensor_to_ego = Eigen::Isometry3d::Identity();  ///< calibrated_sensor
  Eigen::Isometry3d ego_to_global = Eigen::Isometry3d::Identity();  ///< ego_pose at this sweep
  /// The two rotations as the tables hold them (w x y z, not normalised), for a writer that passes
  /// them on to the last bit (a reader normalises them as this one does).
  Eigen::Vector4d sensor_rotation_wxyz = Eigen::Vector4d(1, 0, 0, 0);
  Eigen::Vector4d ego_rotation_wxyz = Eigen::Vector4d(1, 0, 0, 0);
};

/// The tables of a nuScenes-layout dataroot. Only sensor, calibrated_sensor, sample_data,
/// ego_pose, sample, scene and log are read (annotation tables are not needed). Throws IoError
/// naming the table file for a missing table, unparsable JSON, a missing key, a key of the wrong
/// type, or a token that points nowhere.
class NuScenesDataset {
 public:
  /// `dataroot` holds `version/` (e.g. v1.0-mini) and samples/, sweeps/. An empty `version`
  /// finds the one subfolder of dataroot that holds sensor.json (or dataroot itself). A
  /// sample_data `filename` that is absolute or holds '..' is an IoError naming its row: the tables
  /// cannot make the reader open files outside the dataroot.
  explicit NuScenesDataset(const std::string& dataroot, const std::string& version = "");

  const std::string& dataroot() const { return dataroot_; }
  const std::string& tableDirectory() const { return table_dir_; }
  const std::vector<NuScenesScene>& scenes() const { return scenes_; }
  /// Throws std::invalid_argument listing the scenes when `name` is not one of them.
  const NuScenesScene& scene(const std::string& name) const;
  /// Channel names of the sensors with modality "radar", in sensor.json order.
  const std::vector<std::string>& radarChannels() const { return radar_channels_; }
  /// All radar sweeps of a scene, every channel, sorted by timestamp (then channel index).
  std::vector<NuScenesSweep> radarSweeps(const NuScenesScene& scene) const;

 private:
  /// Each scene's sweeps in time order (channel order at equal times), and each scene's span.
  void sortSweepsAndSpanScenes();
  std::string dataroot_;
  std::string table_dir_;
  std::vector<NuScenesScene> scenes_;
  std::vector<std::string> radar_channels_;
  std::map<std::string, std::vector<NuScenesSweep>> sweeps_by_scene_;  ///< scene token → sweeps
};

}  // namespace radar_ndt

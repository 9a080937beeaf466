#pragma once
// A sensor description: one YAML file that says where a recording's radars, IMU and ground truth
// are (ROS topics), how each radar's point fields are named, how it reports Doppler and accuracy,
// where it is mounted and which radar clocks the cycles. Presets for the sensors the project knows
// are files in the same format (share/radar_ndt/sensors/, `preset:NAME`); docs/ros.md documents
// every key. A bad file is an IoError naming the file, the key and the problem.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/io/radar_point_fields.h"

namespace radar_ndt {

/// A mounting as written: x y z (m), roll pitch yaw (rad, applied z-y-x: R = Rz(yaw) Ry(pitch)
/// Rx(roll)), the sensor frame in the vehicle frame (x forward, y left, z up).
struct MountingDescription {
  double x = 0, y = 0, z = 0, roll = 0, pitch = 0, yaw = 0;
  Eigen::Isometry3d transform() const;
};

enum class RadarKind {
  PointCloud,  ///< sensor_msgs/PointCloud2 detections (automotive and 4D radars)
  Scanning,    ///< polar power images (Navtech) as sensor_msgs/Image (PolarImageDescription)
};

/// Where a message's time comes from.
enum class StampSource {
  Header,   ///< the message's header stamp
  Receive,  ///< the bag's receive time (the recorder's clock)
  Auto,     ///< the header stamp, or the receive time when the driver writes zero stamps (said once)
};

/// How a scanning radar's sweep lies in a sensor_msgs/Image (8 bits a bin, mono8 or 8UC1): the
/// image carries only the powers, so the bins, the azimuths and the sweep's timing are described.
struct PolarImageDescription {
  /// true: a row an azimuth, a column a range bin (CFEAR's bags of Oxford); false: a column an
  /// azimuth (Navtech's example ROS driver, CFEAR's bags of MulRan).
  bool rows_are_azimuths = true;
  /// The bins (range_resolution, range_offset_bins) and the direction and zero of the azimuths:
  /// azimuth i of N lies at convention.toVehicleAngle(2π (i + azimuth_offset) / N).
  PolarConvention convention{0.0438, 0.5, 0.0, true};
  double azimuth_offset = 0.0;
  /// Where in the sweep the header stamp is: 0 its first azimuth, 0.5 its middle, 1 its end; the
  /// azimuths' times are spread evenly over `sweep_period` (s; 0: the median interval between sweeps).
  double stamp_position = 0.0;
  double sweep_period = 0.0;
  double max_range = 0.0;  ///< m; 0: every bin
};

struct RadarDescription {
  std::string name;   ///< the channel's name in results and messages (default: the topic)
  std::string topic;  ///< e.g. /RADAR_FRONT
  RadarKind kind = RadarKind::PointCloud;
  /// The sensor's frame id, for a mounting from the recording's TF; empty: the messages' frame_id.
  std::string frame;
  /// Where it sits on the vehicle; none: from the recording's /tf_static or /tf (base frame to `frame`).
  std::optional<MountingDescription> mounting;
  RadarPointFields fields;      ///< point-cloud radars
  PolarImageDescription polar;  ///< scanning radars
};

struct SensorDescription {
  std::string source;  ///< the file it was read from (or "preset:NAME"), for messages
  std::string name;    ///< what it describes, e.g. "nuScenes: five Continental ARS408"
  std::vector<RadarDescription> radars;
  std::string reference;                 ///< the radar (name) that clocks the cycles; empty: the forward-facing one
  std::string base_frame = "base_link";  ///< the vehicle frame of the mountings and the IMU
  StampSource stamps = StampSource::Auto;
  /// sensor_msgs/Imu of the vehicle: the yaw rate is its angular velocity turned into the base
  /// frame by `imu_mounting` (imuYawRate); empty: none.
  std::string imu_topic;
  /// How the IMU's axes lie in the base frame (only the rotation is used: roll pitch yaw); none:
  /// they are the base frame's (z up). An IMU mounted upside down (NTU4DRadLM's VectorNav) is roll π.
  std::optional<MountingDescription> imu_mounting;
  /// The vehicle's forward speed (what --wheels fuses): geometry_msgs/TwistStamped or
  /// nav_msgs/Odometry, twist.linear.x in m/s; empty: none.
  std::string speed_topic;
  /// Ground truth: a nav_msgs/Odometry or geometry_msgs/PoseStamped topic, or tf2_msgs/TFMessage
  /// (/tf) with the transform `ground_truth_parent` → `ground_truth_child`; empty topic: none.
  std::string ground_truth_topic;
  std::string ground_truth_parent = "map", ground_truth_child = "base_link";
};

/// The rotation of the IMU's axes into the base frame (identity without imu_mounting).
Eigen::Matrix3d imuRotation(const SensorDescription& d);
/// The yaw rate (rad/s, about the base frame's z) an IMU reading `gyro` (its own axes) gives.
double imuYawRate(const SensorDescription& d, const Eigen::Vector3d& gyro);

/// Reads a sensor description file; `preset:NAME` reads the preset NAME (sensorPresets()).
/// Throws IoError naming the file, the key (e.g. `radars[2].fields.doppler`) and the problem.
SensorDescription readSensorDescription(const std::string& path);

/// Parses a description from text (the file's contents); `source` names it in errors.
SensorDescription parseSensorDescription(const std::string& text, const std::string& source);

/// The presets there are (names), and the folder they are read from: the source tree's
/// `config/sensors/` in a build, `share/radar_ndt/sensors/` once installed.
std::vector<std::string> sensorPresets();
std::string sensorPresetDirectory();

}  // namespace radar_ndt

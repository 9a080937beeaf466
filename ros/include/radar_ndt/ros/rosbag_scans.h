#pragma once
// A ROS 1 bag of a scanning radar (docs/ros.md): its sweeps as sensor_msgs/Image polar images (8
// bits a bin), laid out as the sensor description's `polar` key says (a row an azimuth, as CFEAR's
// bags of Oxford; or a column an azimuth, as Navtech's example ROS driver), with the IMU and ground
// truth the description names. The image carries neither the azimuths' angles nor their times:
// they are spread evenly over the sweep and over one period. The bag stays open: scans are decoded
// when the run asks for them.

#include <memory>
#include <string>
#include <vector>

#include "radar_ndt/io/scan_source.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/ros/rosbag_sequence.h"

namespace radar_ndt {
namespace ros1 {

/// Throws std::invalid_argument unless the image (sensor_msgs/Image's fields, its data's size) is
/// one polarScanFromImage reads: 8 bits a bin (mono8, 8UC1), not empty, its data as long as its rows.
void checkPolarImage(const std::string& encoding, std::uint32_t height, std::uint32_t width, std::uint32_t step,
                     std::size_t data_size);

/// The sweep in `image` (sensor_msgs/Image's fields) as a polar scan stamped `stamp_us`, its
/// azimuths spread over `period_us`; std::invalid_argument for an encoding other than 8 bits a
/// bin (mono8, 8UC1), data shorter than its rows, or an empty image.
PolarScan polarScanFromImage(const std::string& encoding, std::uint32_t height, std::uint32_t width, std::uint32_t step,
                             const std::vector<std::uint8_t>& data, std::int64_t stamp_us, std::int64_t period_us,
                             const PolarImageDescription& polar);

class RosbagScanSequence : public ScanSource {
 public:
  /// Reads the index of `bag_path` (every sweep's stamp, the IMU, the ground truth) as `sensors`
  /// describes it: one radar, kind scanning. Throws IoError naming the bag and the problem (as
  /// RosbagRadarSequence, and a description of anything but one scanning radar).
  RosbagScanSequence(const std::string& bag_path, const SensorDescription& sensors);
  ~RosbagScanSequence() override;

  std::size_t size() const override;
  std::int64_t stamp(std::size_t k) const override;
  std::string scanName(std::size_t k) const override;
  /// Thread-safe: the bag is read under a lock, the image converted outside it.
  PolarScan load(std::size_t k) const override;
  double periodSeconds() const override;
  const std::string& name() const override;
  std::string formatName() const override { return "rosbag"; }
  /// The ground-truth topic's poses (the radar's own: its frame is the description's child).
  const Trajectory& groundTruth() const override;
  const std::vector<std::string>& indexProblems() const override;
  std::optional<VehicleSignals> gyro(std::string* why_not) const override;
  const BagReadStats& stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ros1
}  // namespace radar_ndt

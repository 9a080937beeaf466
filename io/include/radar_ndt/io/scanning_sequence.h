#pragma once
// A scanning-radar sequence directory: its index of scans, their files and, for Oxford, the
// dataset's ground truth.
//
// Layouts:
//  - oxford: DIR/radar.timestamps, DIR/radar/<stamp>.png (Oxford Radar RobotCar; what radar_sim
//    writes), optional ground truth DIR/gt/radar_odometry.csv (Oxford axes, converted here);
//  - radiate: DIR/Navtech_Polar.txt and DIR/Navtech_Polar/<frame, 6 digits>.png (RADIATE), no
//    ground truth;
//  - boreas: DIR/radar/<stamp>.png (Boreas: no index file, the scans are the directory's PNGs
//    named by their time), optional ground truth DIR/applanix/radar_poses.csv (the radar's own
//    pose at each scan: no extrinsic calibration needed; DIR/calib/ is not read).

#include <cstdint>
#include <string>
#include <vector>

#include "radar_ndt/fields.h"
#include "radar_ndt/io/boreas_scan.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/io/radiate_scan.h"
#include "radar_ndt/io/scan_source.h"
#include "radar_ndt/io/trajectory_io.h"

namespace radar_ndt {

enum class ScanFormat { Oxford, Radiate, Boreas };
template <>
struct EnumNames<ScanFormat> {
  static constexpr const char* what = "scanning format";
  static constexpr EnumName<ScanFormat> names[] = {{ScanFormat::Oxford, "oxford", "Oxford Radar RobotCar"},
                                                   {ScanFormat::Radiate, "radiate", "RADIATE"},
                                                   {ScanFormat::Boreas, "boreas", "Boreas"}};
};

struct ScanningSequenceOptions {
  OxfordPolarOptions oxford;
  RadiatePolarOptions radiate;
  BoreasPolarOptions boreas;
  /// Throws std::invalid_argument naming the setting out of range (bin sizes, expected widths).
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void ScanningSequenceOptions::fields(Visit&& visit) {
  using S = ScanningSequenceOptions;
  visit(&S::oxford, Field("oxford", "Oxford Radar RobotCar scans").scope("oxford"));
  visit(&S::radiate, Field("radiate", "RADIATE scans").scope("radiate"));
  visit(&S::boreas, Field("boreas", "Boreas scans").scope("boreas"));
}

/// The scans of one sequence directory, in time order.
class ScanningSequence : public ScanSource {
 public:
  /// Reads the index (timestamps, frame list; boreas: the PNGs in radar/) and, for oxford and
  /// boreas, the ground truth when present.
  /// Throws IoError naming the file when the index is missing or lists no scan; bad index lines
  /// (unparsable, duplicated or out-of-order timestamps) are left out and listed in indexProblems().
  ScanningSequence(const std::string& dir, ScanFormat format, const ScanningSequenceOptions& options = {});

  std::size_t size() const override { return stamps_.size(); }
  std::int64_t stamp(std::size_t k) const override { return stamps_[k]; }
  const std::string& path(std::size_t k) const { return paths_[k]; }
  std::string scanName(std::size_t k) const override { return paths_[k]; }
  /// Decodes scan k (throws IoError naming the file).
  PolarScan load(std::size_t k) const override;
  /// Median interval between scans (s).
  double periodSeconds() const override { return period_s_; }
  const std::string& name() const override { return name_; }
  const std::string& directory() const { return dir_; }
  ScanFormat format() const { return format_; }
  std::string formatName() const override;
  bool hasGroundTruth() const { return !ground_truth_.empty(); }
  /// SE(2) ground truth in the vehicle frame (x forward, y left), seconds; the first pose is the
  /// first scan the ground truth covers. Empty when the sequence has none.
  const Trajectory& groundTruth() const override { return ground_truth_; }
  /// Index lines (boreas: files in radar/ not named by a time) that were left out, each naming the
  /// file, the line and the problem.
  const std::vector<std::string>& indexProblems() const override { return index_problems_; }
  /// Boreas: applanix/imu.csv; the other layouts have no gyro file.
  std::optional<VehicleSignals> gyro(std::string* why_not) const override;

 private:
  std::string dir_, name_;
  ScanFormat format_;
  ScanningSequenceOptions options_;
  std::vector<std::int64_t> stamps_;
  std::vector<std::string> paths_;
  double period_s_ = 0;
  Trajectory ground_truth_;
  std::vector<std::string> index_problems_;

  void openOxford();
  void openRadiate();
  void openBoreas();
};

}  // namespace radar_ndt

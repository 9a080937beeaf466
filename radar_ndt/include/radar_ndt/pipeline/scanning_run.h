#pragma once
// One odometry run over a scanning-radar sequence (paper, Sec. III-A, III-E, IV-A), every stage
// timed: PNG decode → power threshold (PowerThreshold) → scan-to-scan match (Odometry::addScan).
// Decoding and thresholding the next scan run on a second thread while this one is matched.
// What `radar_odometry --format oxford|radiate` runs.
//
// Layouts:
//  - oxford: DIR/radar.timestamps, DIR/radar/<stamp>.png (Oxford Radar RobotCar; what radar_sim
//    writes), optional ground truth DIR/gt/radar_odometry.csv (Oxford axes, converted here);
//  - radiate: DIR/Navtech_Polar.txt and DIR/Navtech_Polar/<frame, 6 digits>.png (RADIATE), no
//    ground truth.
// A scan that cannot be read is reported with its file and left out; the next one is matched to
// the last good scan over the longer interval.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/odometry/matcher.h"
#include "radar_ndt/odometry/odometry.h"
#include "radar_ndt/frontend/power_threshold.h"
#include "radar_ndt/registration/weighted_ndt_2d.h"

namespace radar_ndt {

enum class ScanFormat { Oxford, Radiate };
/// "oxford" or "radiate"; throws std::invalid_argument otherwise.
ScanFormat parseScanFormat(const std::string& name);
const char* toString(ScanFormat format);

/// The scans of one sequence directory, in time order.
class ScanningSequence {
 public:
  struct Options {
    OxfordPolarOptions oxford;
    RadiatePolarOptions radiate;
  };
  /// Reads the index (timestamps, frame list) and, for oxford, the ground truth when present.
  /// Throws IoError naming the file when the index is missing or lists no scan; bad index lines
  /// (unparsable, duplicated or out-of-order timestamps) are left out and listed in indexProblems().
  ScanningSequence(const std::string& dir, ScanFormat format, const Options& options);
  ScanningSequence(const std::string& dir, ScanFormat format) : ScanningSequence(dir, format, Options()) {}

  std::size_t size() const { return stamps_.size(); }
  std::int64_t stamp(std::size_t k) const { return stamps_[k]; }
  const std::string& path(std::size_t k) const { return paths_[k]; }
  /// Decodes scan k (throws IoError naming the file).
  PolarScan load(std::size_t k) const;
  /// Median interval between scans (s).
  double periodSeconds() const { return period_s_; }
  const std::string& name() const { return name_; }
  ScanFormat format() const { return format_; }
  bool hasGroundTruth() const { return !ground_truth_.empty(); }
  /// SE(2) ground truth in the vehicle frame (x forward, y left), seconds; the first pose is the
  /// first scan the ground truth covers. Empty when the sequence has none.
  const Trajectory& groundTruth() const { return ground_truth_; }
  /// Index lines that were left out, each naming the file, the line and the problem.
  const std::vector<std::string>& indexProblems() const { return index_problems_; }

 private:
  std::string dir_, name_;
  ScanFormat format_;
  Options options_;
  std::vector<std::int64_t> stamps_;
  std::vector<std::string> paths_;
  double period_s_ = 0;
  Trajectory ground_truth_;
  std::vector<std::string> index_problems_;
};

struct ScanningRunOptions {
  Method method = Method::PwNdt;
  ScanningSequence::Options sequence;
  PowerThresholdOptions front_end;
  OdometryOptions odometry;  ///< .scanning holds the pipeline's settings
  std::size_t start = 0;      ///< first scan used
  std::size_t max_scans = 0;  ///< 0: all
  bool prefetch = true;       ///< decode and threshold the next scan on a second thread
  /// Ours: Biber's four overlapping grids. The 2x2-neighbour lookup (the automotive default)
  /// leaves a grid-dependent bias on dense scans: on simulated Oxford scans its frame-to-frame yaw
  /// error was twice as large (README, "Scanning radar odometry").
  CellLookup cell_lookup = CellLookup::OverlappingGrids;
  /// PCL's matchers (pcl-ndt, pcl-icp) get each thresholded scan merged into voxels of this size
  /// (m; centroid, mean time offset, strongest power), as ours merges its source internally;
  /// 0: the full scans (about 4x slower for them, README). Ours always gets the full scans.
  double pcl_voxel_size = 0.25;
};

struct ScanningRunResult {
  std::string sequence;
  ScanFormat format = ScanFormat::Oxford;
  double period_s = 0;
  Trajectory estimate;      ///< one pose per matched scan, seconds, first scan identity
  Trajectory ground_truth;  ///< the sequence's, re-based so the first scan used is identity; may be empty
  std::vector<OdometryStep> steps;
  OdometryCounters counters;
  StageTimes median_ms;  ///< per scan: read = PNG decode, front_end = threshold, match (submap: 0)
  double median_total_ms = 0;   ///< median of per-scan decode + threshold + match (one core)
  double wall_s = 0;            ///< the whole run, wall clock
  double scans_per_second = 0;  ///< end to end, with the prefetch thread
  double median_points = 0;     ///< thresholded points per scan
  /// Index lines left out, and scans that could not be read (bridged), each with the reason.
  std::vector<std::string> problems;
};

/// Called after each scan with its index, its step and its points at the scan's reference time
/// (motion-compensated with the step's velocity when compensation is on), e.g. to build a map.
using ScanCallback = std::function<void(std::size_t, const OdometryStep&, const pcl::PointCloud<PointRadar>&)>;

ScanningRunResult runScanningOdometry(const ScanningSequence& sequence, const ScanningRunOptions& options,
                                      const std::function<void(std::size_t, std::size_t)>& progress = nullptr,
                                      const ScanCallback& on_scan = nullptr);

}  // namespace radar_ndt

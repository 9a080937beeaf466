#pragma once
// One odometry run over a scanning-radar sequence (paper, Sec. III-A, III-E, IV-A), every stage
// timed: PNG decode → power threshold (PowerThreshold) → match (ScanningOdometry). The next scans
// are decoded and thresholded on worker threads while this one is matched, the matches in order on
// one thread at a time (the outputs do not depend on the number of threads). What
// `radar_odometry --format oxford|radiate` runs. A scan that cannot be read is reported with its
// file and bridged; the next one is matched to the keyframe over the longer interval.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "radar_ndt/fields.h"
#include "radar_ndt/frontend/chirp_correction.h"
#include "radar_ndt/frontend/power_threshold.h"
#include "radar_ndt/io/scanning_sequence.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/odometry/matcher.h"
#include "radar_ndt/odometry/scanning_odometry.h"
#include "radar_ndt/pipeline/stage_times.h"

namespace radar_ndt {

struct ScanningRunOptions {
  /// The matcher, at the scanning radars' defaults (MatcherOptions::forScanning).
  MatcherOptions matcher = MatcherOptions::forScanning();
  ScanningSequenceOptions sequence;
  PowerThresholdOptions front_end;
  /// Scans with chirp types (Boreas from 2024): their up/down-chirp range shifts found and undone
  /// before the threshold (frontend/chirp_correction.h).
  ChirpCorrectionOptions chirp;
  ScanningOdometryOptions odometry;
  std::size_t start = 0;      ///< first scan used
  std::size_t max_scans = 0;  ///< 0: all
  /// Threads: the next scans decoded and thresholded on the others while one is matched, the
  /// matches in order. 0: every core the process may use; 1: one thread, nothing ahead.
  int threads = 0;
  /// Matchers that do not merge their source themselves (pcl-ndt, pcl-icp: MatcherUses) get each
  /// thresholded scan merged into voxels of this size (m; centroid, mean time offset, strongest
  /// power), as pw-ndt merges its source internally; 0: the full scans (about 4x slower for them).
  double pcl_voxel_size = 0.25;
  /// Throws std::invalid_argument naming the first setting out of range, including a method that
  /// needs Doppler (doppler, rapp-ndt), which scanning radars do not measure.
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void ScanningRunOptions::fields(Visit&& visit) {
  using S = ScanningRunOptions;
  visit(&S::matcher, Field("matcher", "the matcher"));
  visit(&S::sequence, Field("sequence", "how the sequence's scans are read"));
  visit(&S::front_end, Field("front_end", "the power threshold"));
  visit(&S::chirp, Field("chirp", "the chirp correction (Boreas from 2024)"));
  visit(&S::odometry, Field("odometry", "the scanning odometry"));
  visit(&S::start, Field("start", "first scan used").cli("start"));
  visit(&S::max_scans,
        Field("max_scans", "stop after this many cycles per scene, or scans (0: all)").cli("max-cycles"));
  visit(&S::threads, Field("threads",
                           "threads: the next scans or cycles read and through the front-end on the others "
                           "while one is matched, several nuScenes scenes side by side (outputs "
                           "identical for any number); 0: every core, 1: one thread")
                         .atLeast(0)
                         .cli("threads"));
  visit(&S::pcl_voxel_size, Field("pcl_voxel_size",
                                  "scanning points merged into voxels of this size for matchers that do not merge "
                                  "their source themselves; 0: the full scans")
                                .unit("m")
                                .atLeast(0));
}

/// The defaults for the radar `sequence` was recorded with: the paper's (ScanningRunOptions{}) for
/// every dataset but Boreas scans with chirp types (the radar of its 2024 sequences, told by the
/// first scan's flag bytes), which are brighter: their threshold and power shift are raised so the
/// front-end keeps the share of the image the paper's threshold keeps of Oxford's
/// (docs/data_formats.md, "Boreas defaults"). Apps apply the command line over these.
ScanningRunOptions defaultScanningOptions(const ScanningSequence& sequence);

/// The threshold (and power shift) for Boreas scans with chirp types.
constexpr float kBoreasChirpThreshold = 0.43f;

struct ScanningRunResult {
  std::string sequence;
  std::string format = "oxford";  ///< the layout the scans came from (ScanSource::formatName)
  std::string method = "pw-ndt";
  double period_s = 0;
  Trajectory estimate;      ///< one pose per matched scan, seconds, first scan identity
  Trajectory ground_truth;  ///< the sequence's, re-based so the first scan used is identity; may be empty
  std::vector<OdometryStep> steps;
  OdometryCounters counters;
  StageTimes median_ms;                     ///< per scan: read = PNG decode, front_end = threshold, match (submap: 0)
  double median_total_ms = 0;               ///< median of per-scan decode + threshold + match (one core)
  double wall_s = 0;                        ///< the whole run, wall clock
  double scans_per_second = 0;              ///< end to end, on `threads` threads
  double median_points = 0;                 ///< thresholded points per scan
  int threads = 1;                          ///< threads the run used
  std::string prior = "constant velocity";  ///< what each step's initial guess came from
  /// Index lines left out, scans that could not be read or have no noise floor (a dead sensor;
  /// bridged), and scans no match passed for (constant-velocity motion), each naming its file and
  /// the reason.
  std::vector<std::string> problems;
};

/// Called after each scan with its index, its step and its points at the scan's reference time
/// (motion-compensated with the step's velocity when compensation is on), e.g. to build a map. The
/// callbacks (this and progress) are called in scan order, one at a time, from one of the run's
/// threads (not always the caller's).
using ScanCallback = std::function<void(std::size_t, const OdometryStep&, const pcl::PointCloud<PointRadar>&)>;

/// The run over any source of scans (a dataset folder, a ROS bag).
ScanningRunResult runScanningOdometry(const ScanSource& sequence, const ScanningRunOptions& options,
                                      const std::function<void(std::size_t, std::size_t)>& progress = nullptr,
                                      const ScanCallback& on_scan = nullptr);

/// The scanning run one scan at a time, as scans arrive (the ROS node): the threshold, merging and
/// odometry runScanningOdometry runs, so the same scans give the same steps. A scan without a
/// noise floor is bridged, as in the run.
class ScanningStream {
 public:
  /// Validates `options` (threads, start and max_scans are unused).
  explicit ScanningStream(const ScanningRunOptions& options);
  ~ScanningStream();

  struct Added {
    OdometryStep step;       ///< the step the scan made (bridged: the motion model's)
    bool bridged = false;    ///< the scan could not be used (`problem` says why)
    bool published = false;  ///< the step has a pose in the trajectory (it was not skipped)
    std::string problem;     ///< "" or why the scan was bridged or no match passed, naming `name`
    /// With `want_points`: the scan's points at its reference time (as ScanCallback's).
    pcl::PointCloud<PointRadar> points;
    double front_end_ms = 0;  ///< threshold and merging
  };
  /// Scan `scan` (at its reference time `scan.stamp`, later than the last one's), `name` naming it in
  /// problems.
  Added add(PolarScan scan, const std::string& name, bool want_points = false);

  /// The gyro's yaw rate, which may grow as samples arrive (ScanningOdometry::setYawRate).
  void setYawRate(std::shared_ptr<const TimeSeries> yaw_rate);
  const ScanningOdometry& odometry() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace radar_ndt

#pragma once
// Internal to the scanning runner: the ordered pipeline. Scans are decoded and thresholded (and,
// for PCL's matchers, voxel-merged) on worker threads, several at a time, and handed to the matcher
// one at a time in sequence order, so the odometry sees exactly what a single thread would give it.

#include <cstddef>
#include <functional>
#include <string>

#include <pcl/point_cloud.h>

#include "radar_ndt/frontend/chirp_correction.h"
#include "radar_ndt/frontend/power_threshold.h"
#include "radar_ndt/io/scan_source.h"

namespace radar_ndt {
namespace detail {

/// What the front-end of the scanning pipeline does to each scan: its chirp shifts undone (scans with
/// chirp types), then the threshold.
struct ScanFrontEnd {
  PowerThresholdOptions threshold;
  ChirpCorrectionOptions chirp;
};

/// A decoded and thresholded scan, or why it could not be.
struct PreparedScan {
  std::size_t index = 0;
  pcl::PointCloud<PointRadar>::Ptr cloud;  ///< null when the scan could not be read
  std::string problem;
  double read_ms = 0, front_end_ms = 0;
  ChirpShiftEstimate chirp;  ///< the chirp shifts found and undone (invalid: none)
};

/// Scan k of `sequence`, its chirp shifts undone per `chirp`, through `front_end`, merged into
/// voxels of `voxel` m when > 0.
PreparedScan prepareScan(const ScanSource& sequence, const PowerThreshold& front_end,
                         const ChirpCorrectionOptions& chirp, std::size_t k, double voxel);
/// The same for a scan already decoded (a live one), `name` naming it in the problem;
/// `read_ms` is left to the caller.
PreparedScan prepareDecodedScan(PolarScan scan, const std::string& name, const PowerThreshold& front_end,
                                const ChirpCorrectionOptions& chirp, double voxel);

/// Prepares scans [begin, end) of `sequence` on `threads` threads (runOrdered, ordered_pipeline.h)
/// and calls `consume` with each, in order, one call at a time.
void forEachPreparedScan(const ScanSource& sequence, const ScanFrontEnd& front_end, double voxel, std::size_t begin,
                         std::size_t end, int threads, const std::function<void(PreparedScan&)>& consume);

}  // namespace detail
}  // namespace radar_ndt

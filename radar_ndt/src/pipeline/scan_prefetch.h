#pragma once
// Internal to the scanning runner: each scan decoded and thresholded (and, for PCL's matchers,
// voxel-merged) on a second thread while the one before it is matched.

#include <cstddef>
#include <future>
#include <string>

#include <pcl/point_cloud.h>

#include "radar_ndt/frontend/power_threshold.h"
#include "radar_ndt/pipeline/scanning_sequence.h"

namespace radar_ndt {
namespace detail {

/// A decoded and thresholded scan, or why it could not be.
struct PreparedScan {
  std::size_t index = 0;
  pcl::PointCloud<PointRadar>::Ptr cloud;  ///< null when the scan could not be read
  std::string problem;
  double read_ms = 0, front_end_ms = 0;
};

/// Scan k of `sequence` through `front_end`, merged into voxels of `voxel` m when > 0.
PreparedScan prepareScan(const ScanningSequence& sequence, const PowerThreshold& front_end, std::size_t k,
                         double voxel);

/// Prepares the scan after the one being matched. The front-end is used by one thread at a time
/// (each preparation starts after the previous one was taken).
class ScanPrefetcher {
 public:
  /// `threaded` false: each scan is prepared when it is taken, on the caller's thread.
  ScanPrefetcher(const ScanningSequence& sequence, const PowerThreshold& front_end, double voxel, bool threaded)
      : sequence_(sequence), front_end_(front_end), voxel_(voxel), threaded_(threaded) {}
  /// Starts preparing scan k.
  void start(std::size_t k) {
    next_ = std::async(threaded_ ? std::launch::async : std::launch::deferred,
                       [this, k]() { return prepareScan(sequence_, front_end_, k, voxel_); });
  }
  /// The scan started last (waits for it).
  PreparedScan take() { return next_.get(); }

 private:
  const ScanningSequence& sequence_;
  const PowerThreshold& front_end_;
  double voxel_;
  bool threaded_;
  std::future<PreparedScan> next_;
};

}  // namespace detail
}  // namespace radar_ndt

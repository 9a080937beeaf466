#include "pipeline/scan_pipeline.h"

#include <stdexcept>

#include "detail/run_timing.h"
#include "pipeline/ordered_pipeline.h"
#include "radar_ndt/frontend/voxel_merge.h"

namespace radar_ndt {
namespace detail {

namespace {

/// The threshold and merging of a decoded scan into `p` (its cloud, front_end_ms); throws for a
/// scan without a noise floor.
void thresholdScan(PolarScan& scan, const std::string& name, const PowerThreshold& front_end,
                   const ChirpCorrectionOptions& chirp, double voxel, PreparedScan& p) {
  // A scan without a noise floor is a dead sensor, not a view of an empty world: a real scan's
  // noise floor lights most of its bins (Oxford: over half of them; RADIATE: nearly all).
  // Counting stops once enough bins are lit: a live scan is told after a few thousand bytes.
  const std::size_t needed = (scan.power.size() + 999) / 1000;  // lit · 1000 ≥ size
  std::size_t lit = 0;
  for (auto it = scan.power.begin(); it != scan.power.end() && lit < needed; ++it) lit += *it > 0;
  if (lit < needed)
    throw std::runtime_error(name + ": " + std::to_string(lit) + " of " + std::to_string(scan.power.size()) +
                             " bins above 0: no noise floor, a dead sensor");
  const auto t1 = Clock::now();
  p.chirp = correctChirps(scan, chirp, front_end.options().max_range);
  p.cloud.reset(new pcl::PointCloud<PointRadar>);
  front_end.compute(scan, *p.cloud);
  if (voxel > 0) {
    pcl::PointCloud<PointRadar>::Ptr merged(new pcl::PointCloud<PointRadar>);
    mergeVoxels(*p.cloud, voxel, *merged);
    p.cloud = merged;
  }
  p.front_end_ms = msBetween(t1, Clock::now());
}

}  // namespace

PreparedScan prepareScan(const ScanSource& sequence, const PowerThreshold& front_end,
                         const ChirpCorrectionOptions& chirp, std::size_t k, double voxel) {
  PreparedScan p;
  p.index = k;
  try {
    const auto t0 = Clock::now();
    PolarScan scan = sequence.load(k);
    p.read_ms = msBetween(t0, Clock::now());
    thresholdScan(scan, sequence.scanName(k), front_end, chirp, voxel, p);
  } catch (const std::exception& e) {
    p.cloud.reset();
    p.problem = e.what();
  }
  return p;
}

PreparedScan prepareDecodedScan(PolarScan scan, const std::string& name, const PowerThreshold& front_end,
                                const ChirpCorrectionOptions& chirp, double voxel) {
  PreparedScan p;
  try {
    thresholdScan(scan, name, front_end, chirp, voxel, p);
  } catch (const std::exception& e) {
    p.cloud.reset();
    p.problem = e.what();
  }
  return p;
}

void forEachPreparedScan(const ScanSource& sequence, const ScanFrontEnd& front_end, double voxel, std::size_t begin,
                         std::size_t end, int threads, const std::function<void(PreparedScan&)>& consume) {
  // One front-end for every thread: its geometry cache (megabytes) is built once and shared.
  const PowerThreshold threshold(front_end.threshold);
  runOrdered<PreparedScan>(
      begin, end, threads, [&](std::size_t k) { return prepareScan(sequence, threshold, front_end.chirp, k, voxel); },
      consume);
}

}  // namespace detail
}  // namespace radar_ndt

#include "radar_ndt/pipeline/scanning_sequence.h"
#include "radar_ndt/io/oxford_ground_truth.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/io/radiate_scan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <sys/stat.h>

#include "detail/run_timing.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

using detail::median;
namespace {
bool exists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}
std::string baseName(std::string dir) {
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  const auto slash = dir.find_last_of('/');
  return slash == std::string::npos ? dir : dir.substr(slash + 1);
}
}  // namespace

void ScanningSequenceOptions::validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("ScanningSequenceOptions: " + what); };
  if (!(oxford.convention.range_resolution > 0) || !std::isfinite(oxford.convention.range_resolution))
    fail("oxford.convention.range_resolution (the bin size) must be > 0");
  if (oxford.expected_bins < 0) fail("oxford.expected_bins must be >= 0 (0: any width)");
  if (oxford.encoder_size < 1) fail("oxford.encoder_size must be >= 1");
  if (!(radiate.convention.range_resolution > 0) || !std::isfinite(radiate.convention.range_resolution))
    fail("radiate.convention.range_resolution (the bin size) must be > 0");
  if (radiate.expected_azimuths < 0) fail("radiate.expected_azimuths must be >= 0 (0: any)");
  if (!(radiate.sweep_period > 0)) fail("radiate.sweep_period must be > 0");
}

ScanFormat parseScanFormat(const std::string& name) {
  if (name == "oxford") return ScanFormat::Oxford;
  if (name == "radiate") return ScanFormat::Radiate;
  throw std::invalid_argument("unknown scanning format '" + name + "' (oxford, radiate)");
}

const char* toString(ScanFormat f) {
  return f == ScanFormat::Oxford ? "oxford" : "radiate";
}

ScanningSequence::ScanningSequence(const std::string& dir, ScanFormat format, const ScanningSequenceOptions& options)
    : dir_(dir), name_(baseName(dir)), format_(format), options_(options) {
  if (format == ScanFormat::Oxford) {
    const std::string index = dir + "/radar.timestamps";
    if (!exists(index))
      throw IoError(index, "missing: an Oxford-layout sequence has radar.timestamps and radar/<stamp>.png");
    std::vector<IoError> skipped;
    for (const OxfordStamp& s : readOxfordTimestamps(index, &skipped)) {
      stamps_.push_back(s.stamp);
      paths_.push_back(dir + "/radar/" + std::to_string(s.stamp) + ".png");
    }
    for (const IoError& e : skipped) index_problems_.push_back(e.what());
    const std::string gt_path = dir + "/gt/radar_odometry.csv";
    if (exists(gt_path)) {
      const std::vector<OxfordRelativePose> rows = readOxfordRadarOdometry(gt_path);
      // Chain the relative motions from the first row's destination scan. Oxford axes (x forward,
      // y right, z down) → vehicle axes (x forward, y left, z up): y and yaw change sign. Each pose
      // is keyed by its scan's radar timestamp (source_radar_timestamp: the scan's file name and
      // index stamp, its first azimuth), not by source_timestamp, which in the dataset lies about
      // half a sweep later: keyed by the latter, no pose would meet its scan within a tolerance
      // shorter than that half sweep.
      Pose2 pose = Pose2::Zero();
      if (!rows.empty()) {
        ground_truth_.stamps.push_back(1e-6 * static_cast<double>(rows.front().destination_radar));
        ground_truth_.poses.push_back(toIsometry3(pose));
      }
      for (const auto& r : rows) {
        pose = compose(pose, Pose2(r.x, -r.y, -r.yaw));
        ground_truth_.stamps.push_back(1e-6 * static_cast<double>(r.source_radar));
        ground_truth_.poses.push_back(toIsometry3(pose));
      }
    }
  } else {
    const std::string index = dir + "/Navtech_Polar.txt";
    if (!exists(index))
      throw IoError(index, "missing: a RADIATE sequence has Navtech_Polar.txt and Navtech_Polar/<frame>.png");
    std::vector<IoError> skipped;
    for (const RadiateFrame& f : readRadiateFrameTimes(index, &skipped)) {
      char name[32];
      std::snprintf(name, sizeof name, "%06d.png", f.frame);
      stamps_.push_back(f.stamp_us);
      paths_.push_back(dir + "/Navtech_Polar/" + name);
    }
    for (const IoError& e : skipped) index_problems_.push_back(e.what());
  }
  if (stamps_.empty()) throw IoError(dir, "the sequence lists no scans");
  std::vector<double> d;
  for (std::size_t k = 1; k < stamps_.size(); ++k) d.push_back(1e-6 * static_cast<double>(stamps_[k] - stamps_[k - 1]));
  period_s_ = median(d);
}

PolarScan ScanningSequence::load(std::size_t k) const {
  if (format_ == ScanFormat::Oxford) {
    PolarScan scan = readOxfordPolarPng(paths_[k], options_.oxford);
    scan.stamp = stamps_[k];  // the index's stamp is the scan's reference time
    return scan;
  }
  return readRadiatePolarPng(paths_[k], stamps_[k], options_.radiate);
}

}  // namespace radar_ndt

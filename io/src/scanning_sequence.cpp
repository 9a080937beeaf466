#include "radar_ndt/io/scanning_sequence.h"

#include "radar_ndt/io/boreas_ground_truth.h"
#include "radar_ndt/io/boreas_imu.h"
#include "radar_ndt/io/boreas_scan.h"
#include "radar_ndt/io/oxford_ground_truth.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/io/radiate_scan.h"
#include "radar_ndt/statistics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <sys/stat.h>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

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
/// The upper median (0 for no values).
}  // namespace

void ScanningSequenceOptions::validate() const {
  checkFields(*this, "ScanningSequenceOptions");
}

ScanningSequence::ScanningSequence(const std::string& dir, ScanFormat format, const ScanningSequenceOptions& options)
    : dir_(dir), name_(baseName(dir)), format_(format), options_(options) {
  if (format == ScanFormat::Oxford)
    openOxford();
  else if (format == ScanFormat::Radiate)
    openRadiate();
  else
    openBoreas();
  if (stamps_.empty()) throw IoError(dir, "the sequence lists no scans");
  std::vector<double> d;
  for (std::size_t k = 1; k < stamps_.size(); ++k) d.push_back(1e-6 * static_cast<double>(stamps_[k] - stamps_[k - 1]));
  period_s_ = median(d);
}

void ScanningSequence::openOxford() {
  const std::string& dir = dir_;
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
}

void ScanningSequence::openRadiate() {
  const std::string& dir = dir_;
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

void ScanningSequence::openBoreas() {
  namespace fs = std::filesystem;
  const fs::path radar = fs::path(dir_) / "radar";
  std::error_code ec;
  if (!fs::is_directory(radar, ec))
    throw IoError(radar.string(), "missing: a Boreas sequence has radar/<stamp>.png (and applanix/radar_poses.csv)");
  std::vector<std::pair<std::int64_t, std::string>> scans;
  for (const fs::directory_entry& e : fs::directory_iterator(radar, ec)) {
    if (e.path().extension() != ".png") continue;
    std::int64_t stamp = 0;
    if (boreasTimeMicros(e.path().stem().string(), &stamp))
      scans.emplace_back(stamp, e.path().string());
    else
      index_problems_.push_back(e.path().string() + ": left out, its name is not a timestamp");
  }
  if (ec) throw IoError(radar.string(), "cannot list the scans: " + ec.message());
  std::sort(scans.begin(), scans.end());
  for (std::size_t k = 0; k < scans.size(); ++k) {
    if (k > 0 && scans[k].first == scans[k - 1].first) {
      index_problems_.push_back(scans[k].second + ": left out, the same timestamp as " + scans[k - 1].second);
      continue;
    }
    stamps_.push_back(scans[k].first);
    paths_.push_back(scans[k].second);
  }
  // The radar's own pose at each scan (pyboreas/utils/odometry.py get_sequence_poses_gt, dim 2).
  const std::string gt_path = dir_ + "/applanix/radar_poses.csv";
  if (exists(gt_path)) ground_truth_ = boreasRadarTrajectory(readBoreasPoses(gt_path));
}

PolarScan ScanningSequence::load(std::size_t k) const {
  if (format_ == ScanFormat::Oxford) {
    PolarScan scan = readOxfordPolarPng(paths_[k], options_.oxford);
    scan.stamp = stamps_[k];  // the index's stamp is the scan's reference time
    return scan;
  }
  if (format_ == ScanFormat::Boreas) return readBoreasPolarPng(paths_[k], options_.boreas);
  return readRadiatePolarPng(paths_[k], stamps_[k], options_.radiate);
}

std::string ScanningSequence::formatName() const {
  return toString(format_);
}

std::optional<VehicleSignals> ScanningSequence::gyro(std::string* why_not) const {
  if (format_ != ScanFormat::Boreas) {
    if (why_not)
      *why_not = std::string("--imu: the ") + toString(format_) + " layout has no gyro file (boreas: applanix/imu.csv)";
    return std::nullopt;
  }
  std::optional<VehicleSignals> imu = readBoreasImu(dir_);
  if (!imu && why_not) *why_not = dir_ + "/applanix/imu.csv: missing";
  return imu;
}

}  // namespace radar_ndt

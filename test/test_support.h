#pragma once
// Small helpers shared by the tests that write whole sequences to disk.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "radar_ndt/sim/radar_sim.h"

namespace radar_ndt {
namespace test {

/// A fresh, empty directory under GoogleTest's temporary directory (per process, so parallel
/// ctest runs do not collide).
inline std::string freshTempDir(const std::string& name) {
  const std::filesystem::path p =
      std::filesystem::path(::testing::TempDir()) / ("radar_ndt_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p.string();
}

/// Copies the first `scans` scans of the Oxford-layout sequence in `src` into `dst` (created):
/// their lines of radar.timestamps, their PNGs and the ground-truth rows between them, as text.
inline void copyOxfordSequence(const std::string& src, const std::string& dst, std::size_t scans) {
  namespace fs = std::filesystem;
  fs::create_directories(dst + "/radar");
  fs::create_directories(dst + "/gt");
  std::ifstream index(src + "/radar.timestamps");
  std::ofstream index_out(dst + "/radar.timestamps");
  std::string line;
  for (std::size_t k = 0; k < scans && std::getline(index, line); ++k) {
    index_out << line << '\n';
    const std::string png = "/radar/" + line.substr(0, line.find(' ')) + ".png";
    fs::copy_file(src + png, dst + png, fs::copy_options::overwrite_existing);
  }
  std::ifstream gt(src + "/gt/radar_odometry.csv");
  std::ofstream gt_out(dst + "/gt/radar_odometry.csv");
  for (std::size_t k = 0; k < scans && std::getline(gt, line); ++k)
    gt_out << line << '\n';  // the header, then scans − 1 rows
}

/// Writes a simulated Oxford-layout sequence along `ego` with the calibrated simulator: the oxford
/// profile's sensor and world.
inline void writeOxfordProfileSequence(const std::string& dir, const sim::SimTrajectory& ego,
                                       const sim::SequenceOptions& seq) {
  sim::WorldOptions world;
  sim::ScanningOptions scanning;
  sim::applyProfile(sim::ScanningProfile::Oxford, world, scanning);
  sim::writeScanningSequence(dir, ego, world, scanning, seq);
}

/// The bytes of a file ("" when it cannot be read).
inline std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Writes `bytes` to `path` as they are (a test's file, good or broken).
inline void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

}  // namespace test
}  // namespace radar_ndt

#pragma once
// Small helpers shared by the tests that write whole sequences to disk.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

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

/// The bytes of a file ("" when it cannot be read).
inline std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace test
}  // namespace radar_ndt

// libFuzzer target: Oxford `gt/radar_odometry.csv` (readOxfordRadarOdometry).
#include <cmath>
#include <cstdint>

#include "fuzz_support.h"
#include "radar_ndt/io/oxford_ground_truth.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using radar_ndt::fuzz::finding;
  const std::string path = radar_ndt::fuzz::writeBytes("radar_odometry.csv", data, size);
  radar_ndt::fuzz::readOrIoError(path, [&] {
    const auto rows = radar_ndt::readOxfordRadarOdometry(path);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& r = rows[i];
      for (double v : {r.x, r.y, r.z, r.roll, r.pitch, r.yaw})
        if (!std::isfinite(v)) finding("non-finite relative pose");
      if (i > 0 && r.destination != rows[i - 1].source) finding("rows do not chain");
    }
  });
  return 0;
}

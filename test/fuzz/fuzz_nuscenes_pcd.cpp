// libFuzzer target: nuScenes radar PCD files (readNuScenesRadarPcd, ascii / binary /
// binary_compressed) and the PointRadar PCD loader (loadPointRadarPcd: our header check in front
// of PCL's reader).
#include <cmath>
#include <cstdint>

#include "fuzz_support.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/io/pcd.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using radar_ndt::fuzz::finding;
  const std::string path = radar_ndt::fuzz::writeBytes("sweep.pcd", data, size);
  radar_ndt::NuScenesRadarFilter all;  // keep every point so the post-conditions see them all
  all.invalid_states.clear();
  all.ambig_states.clear();
  all.max_range = 1e30;
  radar_ndt::fuzz::readOrIoError(path, [&] {
    radar_ndt::NuScenesPcdStats stats;
    const auto cloud = radar_ndt::readNuScenesRadarPcd(path, all, 3, &stats);
    if (cloud.size() != stats.kept ||
        stats.kept + stats.dropped_by_filter + stats.dropped_non_finite != stats.points_in_file)
      finding("point counts do not add up");
    for (const auto& p : cloud) {
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(p.doppler))
        finding("non-finite point kept");
      if (p.sensor_id != 3) finding("sensor id not set");
    }
  });
  radar_ndt::fuzz::readOrIoError(path,
                                 [&] { radar_ndt::readNuScenesRadarPcd(path, radar_ndt::NuScenesRadarFilter{}, 0); });
  radar_ndt::fuzz::readOrIoError(path, [&] { radar_ndt::loadPointRadarPcd(path); });
  return 0;
}

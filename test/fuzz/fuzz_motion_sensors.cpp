// libFuzzer target: the motion sensors' files (a Boreas applanix/imu.csv, a nuScenes CAN bus
// message file as the yaw rate, the rear wheels and the ms_imu messages read it). The first input
// byte chooses the reader; the rest is the file.
#include <cmath>
#include <cstdint>
#include <filesystem>

#include "fuzz_support.h"
#include "radar_ndt/io/boreas_imu.h"
#include "radar_ndt/io/nuscenes_can_bus.h"

namespace {

void checkSeries(const radar_ndt::TimeSeries& s) {
  using radar_ndt::fuzz::finding;
  if (s.stamps_us.size() != s.values.size()) finding("stamps and values differ in count");
  for (std::size_t i = 0; i < s.values.size(); ++i) {
    if (!std::isfinite(s.values[i])) finding("a non-finite value was returned");
    if (i > 0 && !(s.stamps_us[i] > s.stamps_us[i - 1])) finding("stamps not strictly increasing");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using radar_ndt::fuzz::finding;
  if (size < 1) return 0;
  const int kind = data[0] % 4;
  if (kind == 0) {
    const std::string path = radar_ndt::fuzz::writeBytes("imu.csv", data + 1, size - 1);
    radar_ndt::fuzz::readOrIoError(path, [&] {
      const auto rows = radar_ndt::readBoreasImuFile(path);
      if (rows.size() < 2) finding("fewer than two rows returned instead of an error");
      for (std::size_t i = 0; i < rows.size(); ++i) {
        if (!rows[i].angular_velocity.allFinite() || !rows[i].acceleration.allFinite()) finding("non-finite row");
        if (i > 0 && !(rows[i].stamp_us > rows[i - 1].stamp_us)) finding("stamps not strictly increasing");
      }
    });
    return 0;
  }
  if (kind == 3) {
    // The devkit's layout: <dataroot>/can_bus/<scene>_ms_imu.json.
    const std::string dataroot = radar_ndt::fuzz::scratchDir() + "/dataroot";
    std::filesystem::create_directories(dataroot + "/can_bus");
    const std::string path = radar_ndt::fuzz::writeBytes("dataroot/can_bus/scene-0001_ms_imu.json", data + 1, size - 1);
    radar_ndt::fuzz::readOrIoError(path, [&] {
      const auto messages = radar_ndt::readNuScenesImuMessages(dataroot, "scene-0001");
      if (!messages) finding("no messages although the can_bus folder is there");
    });
    return 0;
  }
  const std::string path = radar_ndt::fuzz::writeBytes("can_bus.json", data + 1, size - 1);
  radar_ndt::fuzz::readOrIoError(path, [&] {
    std::size_t dropped = 0;
    if (kind == 1)
      checkSeries(radar_ndt::readCanBusSeries(path, {"rotation_rate"}, 2, &dropped));
    else
      checkSeries(radar_ndt::readCanBusSeries(path, {"RL_wheel_speed", "RR_wheel_speed"}, -1, &dropped));
  });
  return 0;
}

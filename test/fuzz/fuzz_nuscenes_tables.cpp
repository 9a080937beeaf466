// libFuzzer target: the nuScenes JSON tables (NuScenesDataset). A small consistent dataroot (two
// radars and a camera, one scene) is written once; each input replaces one of its seven tables:
// the first byte chooses which, the rest is the table's text. Then every scene's sweeps are listed.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>

#include "fuzz_support.h"
#include "radar_ndt/io/nuscenes.h"

namespace {

struct TableFile {
  const char* name;
  const char* text;
};

const TableFile kTables[] = {
    {"sensor.json",
     R"([{"token": "s_front", "channel": "RADAR_FRONT", "modality": "radar"},
{"token": "s_left", "channel": "RADAR_FRONT_LEFT", "modality": "radar"},
{"token": "s_cam", "channel": "CAM_FRONT", "modality": "camera"}])"},
    {"calibrated_sensor.json",
     R"([{"token": "c_front", "sensor_token": "s_front", "translation": [3.4, 0.0, 0.5],
 "rotation": [1.0, 0.0, 0.0, 0.0], "camera_intrinsic": []},
{"token": "c_left", "sensor_token": "s_left", "translation": [2.4, 0.8, 0.5],
 "rotation": [0.7071068, 0.0, 0.0, 0.7071068], "camera_intrinsic": []},
{"token": "c_cam", "sensor_token": "s_cam", "translation": [1.7, 0.0, 1.5], "rotation": [0.5, -0.5, 0.5, -0.5],
 "camera_intrinsic": [[1266.4, 0.0, 816.3], [0.0, 1266.4, 491.5], [0.0, 0.0, 1.0]]}])"},
    {"ego_pose.json",
     R"([{"token": "e1", "timestamp": 1531883530449377, "rotation": [0.57, -0.0, 0.0, -0.82],
 "translation": [411.3, 1180.9, 0.0]},
{"token": "e2", "timestamp": 1531883530526245, "rotation": [0.57, -0.0, 0.0, -0.82],
 "translation": [411.9, 1180.1, 0.0]},
{"token": "e3", "timestamp": 1531883530540000, "rotation": [1.0, 0.0, 0.0, 0.0],
 "translation": [412.0, 1180.0, 0.0]}])"},
    {"sample.json",
     R"([{"token": "k1", "timestamp": 1531883530449377, "prev": "", "next": "k2", "scene_token": "sc1"},
{"token": "k2", "timestamp": 1531883531000000, "prev": "k1", "next": "", "scene_token": "sc1"}])"},
    {"scene.json",
     R"([{"token": "sc1", "log_token": "l1", "nbr_samples": 2, "first_sample_token": "k1",
 "last_sample_token": "k2", "name": "scene-0001", "description": "Night, rain"}])"},
    {"log.json",
     R"([{"token": "l1", "logfile": "n015-2018-07-18-11-07-57+0800", "vehicle": "n015",
 "date_captured": "2018-07-18", "location": "singapore-onenorth"}])"},
    {"sample_data.json",
     R"([{"token": "d1", "sample_token": "k1", "ego_pose_token": "e1", "calibrated_sensor_token": "c_front",
 "timestamp": 1531883530449377, "fileformat": "pcd", "is_key_frame": true, "height": 0, "width": 0,
 "filename": "samples/RADAR_FRONT/a.pcd", "prev": "", "next": "d2"},
{"token": "d2", "sample_token": "k1", "ego_pose_token": "e2", "calibrated_sensor_token": "c_front",
 "timestamp": 1531883530526245, "fileformat": "pcd", "is_key_frame": false, "height": 0, "width": 0,
 "filename": "sweeps/RADAR_FRONT/b.pcd", "prev": "d1", "next": ""},
{"token": "d3", "sample_token": "k2", "ego_pose_token": "e3", "calibrated_sensor_token": "c_left",
 "timestamp": 1531883530540000, "fileformat": "pcd", "is_key_frame": false, "height": 0, "width": 0,
 "filename": "sweeps/RADAR_FRONT_LEFT/c.pcd", "prev": "", "next": ""},
{"token": "d4", "sample_token": "k2", "ego_pose_token": "e3", "calibrated_sensor_token": "c_cam",
 "timestamp": 1531883530540000, "fileformat": "jpg", "is_key_frame": true, "height": 900, "width": 1600,
 "filename": "samples/CAM_FRONT/d.jpg", "prev": "", "next": ""}])"},
};
constexpr std::size_t kTableCount = sizeof(kTables) / sizeof(kTables[0]);

std::string tableDir() {
  return radar_ndt::fuzz::scratchDir() + "/v1.0-fuzz";
}

void writeTable(std::size_t i, const std::string& text) {
  std::ofstream(tableDir() + "/" + kTables[i].name, std::ios::binary | std::ios::trunc) << text;
}

}  // namespace

// RADAR_NDT_FUZZ_WRITE_SEEDS=DIR: write one seed per table (selector byte + the table) and exit.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::filesystem::create_directories(tableDir());
  for (std::size_t i = 0; i < kTableCount; ++i) writeTable(i, kTables[i].text);
  if (const char* dir = std::getenv("RADAR_NDT_FUZZ_WRITE_SEEDS")) {
    std::filesystem::create_directories(dir);
    for (std::size_t i = 0; i < kTableCount; ++i)
      std::ofstream(std::string(dir) + "/builtin_" + kTables[i].name, std::ios::binary)
          << static_cast<char>(i) << kTables[i].text;
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using radar_ndt::fuzz::finding;
  if (size < 1) return 0;
  const std::size_t which = data[0] % kTableCount;
  writeTable(which, std::string(reinterpret_cast<const char*>(data + 1), size - 1));
  const std::string table_path = tableDir() + "/" + kTables[which].name;
  try {
    const radar_ndt::NuScenesDataset dataset(radar_ndt::fuzz::scratchDir());
    for (const auto& scene : dataset.scenes()) {
      const auto sweeps = dataset.radarSweeps(scene);
      for (std::size_t i = 0; i < sweeps.size(); ++i) {
        const auto& s = sweeps[i];
        if (s.channel_index >= dataset.radarChannels().size() || s.channel != dataset.radarChannels()[s.channel_index])
          finding("sweep channel does not match the radar channel list");
        if (!s.sensor_to_ego.matrix().allFinite() || !s.ego_to_global.matrix().allFinite())
          finding("non-finite calibration or pose");
        if (i > 0 && s.timestamp_us < sweeps[i - 1].timestamp_us) finding("sweeps not in time order");
      }
    }
  } catch (const radar_ndt::IoError& e) {
    // The error names a table file, or the dataroot / table directory when the layout is wrong.
    const std::string what = e.what();
    if (what.find(radar_ndt::fuzz::scratchDir()) == std::string::npos) finding("IoError does not name a file: " + what);
  }
  writeTable(which, kTables[which].text);
  return 0;
}

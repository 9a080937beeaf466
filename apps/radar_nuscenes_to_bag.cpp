// radar_nuscenes_to_bag: nuScenes scenes as ROS 1 bags in nuscenes2bag's layout (radar topics with
// the PCD's fields, /tf, /imu), so that nuScenes users and the tests have bags of the shared
// scenes; `radar_odometry --format rosbag --sensors preset:nuscenes_ars408` reads them.
#include <filesystem>
#include <iostream>

#include <pcl/console/print.h>

#include "app_common.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/ros/nuscenes_bag.h"

using namespace radar_ndt;
namespace po = boost::program_options;

int main(int argc, char** argv) {
  std::string dataroot, version, scene_name, out, compression_text;
  po::options_description opts("Options");
  // clang-format off
  opts.add_options()
    ("help,h", "print this help and exit")
    ("dataroot", po::value(&dataroot)->required(), "the nuScenes dataroot (holds v1.0-*/, samples/, sweeps/, can_bus/)")
    ("version", po::value(&version)->default_value(""), "table folder under dataroot (default: the one holding sensor.json)")
    ("scene", po::value(&scene_name)->default_value("all"), "scene name, or 'all'")
    ("out", po::value(&out)->required(), "the folder the bags are written to, one <scene>.bag each (created)")
    ("compression", po::value(&compression_text)->default_value("none"), "the bag's chunks: none | bz2 | lz4");
  // clang-format on
  const std::string usage =
      "Usage: radar_nuscenes_to_bag --dataroot DIR [--scene NAME|all] --out DIR [--compression none|bz2|lz4]\n"
      "Writes each scene's radar sweeps (sensor_msgs/PointCloud2 on /RADAR_*, the PCD's fields as they are), the\n"
      "ego poses and mountings (/tf: map -> base_link, base_link -> RADAR_*) and the CAN bus's ms_imu (/imu) as a\n"
      "ROS 1 bag in nuscenes2bag's layout (docs/ros.md).";
  po::variables_map vm;
  const int rc = apps::parseCommandLine(argc, argv, opts, usage, vm);
  if (rc >= 0) return rc;
  return apps::runGuarded("radar_nuscenes_to_bag", [&]() {
    const ros1::BagCompression compression = ros1::parseBagCompression(compression_text);
    const NuScenesDataset dataset(dataroot, version);
    std::filesystem::create_directories(out);
    for (const auto& scene : dataset.scenes()) {
      if (scene_name != "all" && scene.name != scene_name) continue;
      const std::string path = out + "/" + scene.name + ".bag";
      const ros1::NuScenesBagStats s = ros1::writeNuScenesBag(dataset, scene, path, compression);
      pcl::console::print_info("Wrote %s: %zu radar clouds, %zu /tf, %zu /imu messages\n", path.c_str(),
                               s.radar_messages, s.tf_messages, s.imu_messages);
    }
    if (scene_name != "all") dataset.scene(scene_name);  // a scene that is not there: said
    return 0;
  });
}

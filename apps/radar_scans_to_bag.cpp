// radar_scans_to_bag: a scanning-radar sequence (Oxford, Boreas, RADIATE) as a ROS 1 bag in the
// layout of CFEAR's bags of Oxford (/Navtech/Polar sensor_msgs/Image, a row an azimuth; /gt; /imu),
// so that the scanning pipeline over ROS is run and tested on real scans;
// `radar_odometry --format rosbag --sensors preset:navtech_oxford` reads them.
#include <iostream>

#include <pcl/console/print.h>

#include "app_common.h"
#include "radar_ndt/io/scanning_sequence.h"
#include "radar_ndt/ros/scan_bag.h"

using namespace radar_ndt;
namespace po = boost::program_options;

int main(int argc, char** argv) {
  std::string format, sequence, out, compression_text;
  po::options_description opts("Options");
  // clang-format off
  opts.add_options()
    ("help,h", "print this help and exit")
    ("format", po::value(&format)->required(), "the sequence's layout: oxford | boreas | radiate")
    ("sequence", po::value(&sequence)->required(), "the sequence folder (as radar_odometry --sequence)")
    ("out", po::value(&out)->required(), "the bag to write (replaced)")
    ("compression", po::value(&compression_text)->default_value("none"), "the bag's chunks: none | bz2 | lz4");
  // clang-format on
  const std::string usage =
      "Usage: radar_scans_to_bag --format oxford|boreas|radiate --sequence DIR --out FILE.bag [--compression "
      "none|bz2|lz4]\n"
      "Writes the sequence's scans as sensor_msgs/Image on /Navtech/Polar (mono8, a row an azimuth, the power\n"
      "bins only, stamped with the scan's time), its ground truth as nav_msgs/Odometry on /gt and Boreas' gyro as\n"
      "sensor_msgs/Imu on /imu: the layout of CFEAR's bags of Oxford (docs/ros.md).";
  po::variables_map vm;
  const int rc = apps::parseCommandLine(argc, argv, opts, usage, vm);
  if (rc >= 0) return rc;
  return apps::runGuarded("radar_scans_to_bag", [&]() {
    const ros1::BagCompression compression = ros1::parseBagCompression(compression_text);
    const ScanningSequence s(sequence, parseEnum<ScanFormat>(format));
    const ros1::ScanBagStats stats = ros1::writeScanBag(s, out, compression);
    pcl::console::print_info("Wrote %s: %zu scans (%zu unreadable left out), %zu /gt, %zu /imu messages\n", out.c_str(),
                             stats.scans, stats.unreadable, stats.ground_truth, stats.imu);
    return 0;
  });
}

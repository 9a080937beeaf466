// radar_paper_tables: the paper's tables reproduced on the data given, every method through the
// same front-end, guesses and failure handling (paper_tables/tables.h). The pipeline options are
// radar_odometry's (docs/apps.md).
#include <unistd.h>

#include "app_common.h"
#include "paper_tables/tables.h"
#include "pipeline_options.h"

using namespace radar_ndt;
namespace po = boost::program_options;

namespace {

/// The command line over the defaults for the first sequence's radar (defaultScanningOptions).
ScanningRunOptions scanningTableOptions(const po::variables_map& vm) {
  const ScanningSequence first(apps::sequenceDirs(vm).front(), parseEnum<ScanFormat>(vm["format"].as<std::string>()),
                               apps::scanningOptions(vm).sequence);
  return apps::scanningOptions(vm, defaultScanningOptions(first));
}

po::options_description tableOptions() {
  po::options_description opts("Options");
  opts.add_options()("help,h", "print this help and exit");
  apps::addPipelineOptions(opts);
  // clang-format off
  opts.add_options()
    ("json", po::bool_switch(), "print the table as JSON")
    ("noise-calibration", po::bool_switch(),
     "nuscenes: instead of the table, calibrate the fusion's covariances on every scene with "
     "--method (default pw-ndt) and check them leaving each scene out (mean NEES); then, per scene and axis, "
     "what the match adds to the Doppler motion (errors' RMS and correlation, the best "
     "fixed fusion weight the ground truth would choose)")
    ("sweep-scans", po::value<std::size_t>()->default_value(400),
     "oxford: scans of the first sequence the PCL grid sweep is scored on "
     "(--max-cycles caps every other run)");
  // clang-format on
  return opts;
}

const char* const kUsage =
    "Usage: radar_paper_tables --format nuscenes --dataroot DIR [--scene NAME|all] [--noise-calibration] [pipeline "
    "options] [--json]\n"
    "       radar_paper_tables --format oxford --sequence DIR... [--max-cycles N] [--sweep-scans N] [pipeline "
    "options] [--json]\n"
    "nuscenes: the paper's nuScenes table on every scene: N = 1, 3, 5, 10 for pcl-icp and pw-ndt, N = 1 for doppler "
    "and\n"
    "rapp-ndt, in the paper's mode (submap to submap); then the four through the default pipeline; 1m metric, mean "
    "over\n"
    "scenes. --noise-calibration: the fusion's covariances calibrated with --method on every scene and checked "
    "leaving each\n"
    "scene out. oxford, boreas: on every --sequence (with ground truth), ours vs PCL's NDT and ICP (documented "
    "settings and "
    "the best\n"
    "of a grid sweep) and the paper's ablations; KITTI metric. --method is ignored but by --noise-calibration.";

}  // namespace

int main(int argc, char** argv) {
  const po::options_description opts = tableOptions();
  po::variables_map vm;
  const int rc = apps::parseCommandLine(argc, argv, opts, kUsage, vm);
  if (rc >= 0) return rc;
  return apps::runGuarded("radar_paper_tables", [&]() {
    const bool json_out = vm["json"].as<bool>();
    const bool progress_on = !vm["quiet"].as<bool>() && isatty(STDERR_FILENO);
    const std::string format = vm["format"].as<std::string>();
    if (apps::pipelineOf(format) == apps::Pipeline::Scanning)
      return apps::runScanningTable(scanningTableOptions(vm), parseEnum<ScanFormat>(format), apps::sequenceDirs(vm),
                                    vm["sweep-scans"].as<std::size_t>(), json_out, progress_on);
    const AutomotiveRunOptions options = apps::automotiveOptions(vm);
    const NuScenesDataset dataset = apps::openDataset(vm);
    if (vm["noise-calibration"].as<bool>())
      return apps::runNoiseCalibration(options, dataset, apps::selectScenes(dataset, vm), json_out, progress_on);
    return apps::runNuScenesTable(options, dataset, apps::selectScenes(dataset, vm), json_out, progress_on);
  });
}

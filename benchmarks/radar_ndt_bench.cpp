// radar_ndt_bench: times and scores WeightedNDT2D against PCL's NDT, NDT2D and ICP on the same
// synthetic radar-like scan pairs with known transforms (identity initial guess); --nuscenes: the
// registered matchers on real automotive submap pairs; --oxford: the scanning front-end's two paths
// on a scan sequence (ndt_bench/ndt_bench.h).
#include <algorithm>
#include <sstream>
#include <string>

#include "app_common.h"
#include "ndt_bench/ndt_bench.h"

using namespace radar_ndt;
namespace po = boost::program_options;

namespace {

/// Which benchmark (the synthetic one when neither path is given).
struct Args {
  std::string nuscenes_root, oxford_dir;
  std::size_t nuscenes_stride = 5;
};

po::options_description options(Args& a, apps::SyntheticBench& b) {
  po::options_description o("Options");
  // clang-format off
  o.add_options()
    ("help,h", "print this help and exit")
    ("pairs", po::value(&b.pairs)->default_value(24), "scan pairs (sizes cycle through --sizes)")
    ("sizes", po::value(&b.sizes_text)->default_value("5000,10000,20000"), "points per scan, comma-separated")
    ("repeats", po::value(&b.repeats)->default_value(1), "time each pair this many times (median kept)")
    ("seed", po::value(&b.seed)->default_value(1), "first seed; pair k uses seed + k")
    ("grid", po::value(&b.grid)->default_value(3.0), "grid size g (m) for WeightedNDT2D and PCL's NDT resolution")
    ("shift", po::value(&b.shift)->default_value(0.3, "0.3"), "WeightedNDT2D power shift s (clutter power is 0.02..0.3)")
    ("noise", po::value(&b.noise)->default_value(0.05, "0.05"), "position noise of the scans (m)")
    ("clutter", po::value(&b.clutter)->default_value(0.15, "0.15"), "fraction of low-power clutter points")
    ("max-translation", po::value(&b.max_t)->default_value(2.0), "true transforms up to this translation (m)")
    ("max-rotation", po::value(&b.max_r)->default_value(3.0), "and this rotation (deg)")
    ("icp-distance", po::value(&b.icp_dist)->default_value(5.0), "ICP max correspondence distance (m)")
    ("no-icp", po::bool_switch(), "skip pcl::IterativeClosestPoint")
    ("no-ndt2d", po::bool_switch(), "skip pcl::NormalDistributionsTransform2D")
    ("variants", po::bool_switch(), "also run WeightedNDT2D with overlapping grids, and without the source voxel merge")
    ("nuscenes", po::value(&a.nuscenes_root),
     "instead: real N = 3 submap pairs from this nuScenes-layout dataroot (every registered matcher that needs "
     "no Doppler weights: pw-ndt, PCL NDT, PCL ICP, and any a user registered)")
    ("oxford", po::value(&a.oxford_dir),
     "instead: the scanning front-end's Cartesian and polar paths on the scan pairs of this Oxford-layout sequence "
     "(e.g. radar_sim's)")
    ("nuscenes-stride", po::value(&a.nuscenes_stride)->default_value(5), "with --nuscenes: every k-th cycle")
    ("json", po::bool_switch(&b.json),
     "print one JSON object: per method ms_median, trans_err_m, rot_err_deg, converged_frac");
  // clang-format on
  return o;
}

const char* const kUsage =
    "Usage: radar_ndt_bench [--pairs N] [--sizes 5000,10000,20000] [--json]\n"
    "Synthetic 2D radar-like scan pairs (walls, poles, arcs, low-power clutter, noise) with known\n"
    "transforms; every method aligns the same pairs from the identity. Time = setInputSource +\n"
    "setInputTarget + align, single thread.\n"
    "       radar_ndt_bench --nuscenes DIR | --oxford DIR   (real submap pairs | scanning front-ends)";

}  // namespace

int main(int argc, char** argv) {
  Args a;
  apps::SyntheticBench b;
  const po::options_description opts = options(a, b);
  po::variables_map vm;
  const int rc = apps::parseCommandLine(argc, argv, opts, kUsage, vm);
  if (rc >= 0) return rc;
  b.with_icp = !vm["no-icp"].as<bool>();
  b.with_ndt2d = !vm["no-ndt2d"].as<bool>();
  b.variants = vm["variants"].as<bool>();
  return apps::runGuarded("radar_ndt_bench", [&]() {
    if (!a.oxford_dir.empty()) return apps::benchScanningFrontEnds(a.oxford_dir, b.json);
    if (!a.nuscenes_root.empty())
      return apps::benchNuScenes(a.nuscenes_root, std::max<std::size_t>(1, a.nuscenes_stride), b.json);
    std::stringstream ss(b.sizes_text);
    for (std::string w; std::getline(ss, w, ',');) b.sizes.push_back(std::stoul(w));
    if (b.sizes.empty()) throw std::invalid_argument("--sizes is empty");
    return apps::benchSynthetic(b);
  });
}

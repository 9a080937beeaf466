// radar_ndt_bench: times and scores WeightedNDT2D against PCL's NDT, NDT2D and ICP on the same
// synthetic radar-like scan pairs with known transforms (identity initial guess); --nuscenes: on
// real automotive submap pairs; --oxford: the scanning front-end's two paths on a scan sequence.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>
#include <pcl/registration/ndt_2d.h>

#include "app_common.h"
#include "radar_ndt/frontend/automotive_front_end.h"
#include "radar_ndt/frontend/power_threshold.h"
#include "radar_ndt/frontend/probabilistic_submap.h"
#include "radar_ndt/io/nuscenes_sequence.h"
#include "radar_ndt/io/oxford_ground_truth.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/odometry/matcher.h"
#include "radar_ndt/odometry/matcher_registry.h"
#include "radar_ndt/registration/weighted_ndt_2d.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/sim/synthetic_scan.h"

using namespace radar_ndt;
namespace po = boost::program_options;
using PointT = pcl::PointXYZI;  // every method sees the same clouds; intensity = power
using Cloud = pcl::PointCloud<PointT>;
using Reg = pcl::Registration<PointT, PointT>;

namespace {

struct BenchMethod {
  std::string name;
  std::string settings;
  std::function<Reg::Ptr()> make;
};

struct Sample {
  double ms, trans_err, rot_err_deg;
  bool converged;
  std::size_t points;
};

using apps::median;

Cloud::Ptr toXYZI(const pcl::PointCloud<PointRadar>& in) {
  Cloud::Ptr out(new Cloud);
  out->reserve(in.size());
  for (const auto& p : in) {
    PointT q;
    q.x = p.x;
    q.y = p.y;
    q.z = 0;
    q.intensity = p.power;
    out->push_back(q);
  }
  return out;
}

}  // namespace

/// Real submap pairs: N = 3 probabilistic submaps of consecutive cycles of every scene under
/// `dataroot` (every `stride`-th cycle), each method started from the Doppler integral; errors
/// against the ground-truth motion between the two cycles.
int benchNuScenes(const std::string& dataroot, std::size_t stride, bool json) {
  using namespace radar_ndt;
  const NuScenesDataset ds(dataroot);
  const AutomotiveFrontEnd fe;
  struct Pair {
    pcl::PointCloud<PointRadar>::Ptr source, target;
    Pose2 guess, truth;
  };
  std::vector<Pair> pairs;
  for (const auto& scene : ds.scenes()) {
    const NuScenesRadarSequence seq(ds, scene, NuScenesSequenceOptions{});
    ProbabilisticSubmap submap(3);
    pcl::PointCloud<PointRadar>::Ptr previous;
    for (std::size_t k = 0; k < seq.size(); ++k) {
      const ProcessedCycle c = fe.process(seq.load(k));
      const double dt = k ? 1e-6 * static_cast<double>(seq.timestamp(k) - seq.timestamp(k - 1)) : 0.0;
      submap.add(*c.cloud, c.ego.velocity, c.ego.covariance, dt);
      auto current = submap.cloud();
      if (k >= 3 && k % stride == 0)
        pairs.push_back({current, previous, submap.lastMotion(),
                         between(toPose2(seq.groundTruth(k - 1)), toPose2(seq.groundTruth(k)))});
      previous = current;
    }
  }
  nlohmann::json j;
  j["pairs"] = pairs.size();
  if (!json)
    std::printf(
        "radar_ndt_bench --nuscenes: %zu real submap pairs (N = 3), Doppler initial guess\n%-10s %10s %14s %14s\n",
        pairs.size(), "method", "ms median", "trans err m", "rot err deg");
  // Every registered matcher that matches and needs nothing beyond the submaps (Rapp's Doppler
  // weights are the odometry's), at the automotive defaults.
  for (const std::string& m : matcherNames()) {
    const MatcherUses& uses = findMatcher(m).uses;
    if (uses.needs_doppler || uses.doppler_weights) continue;
    MatcherOptions options = MatcherOptions::forAutomotive();
    options.method = m;
    RadarRegistration::Ptr reg = makeMatcher(options).registrationPtr();
    if (!reg) continue;
    std::vector<double> ms;
    double et = 0, er = 0;
    pcl::PointCloud<PointRadar> out;
    for (const auto& p : pairs) {
      const auto t0 = std::chrono::steady_clock::now();
      reg->setInputTarget(p.target);
      reg->setInputSource(p.source);
      reg->align(out, toMatrix4<float>(p.guess));
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      const Pose2 e = between(p.truth, toPose2(reg->getFinalTransformation()));
      et += e.head<2>().norm();
      er += std::abs(e.z()) * 180.0 / kPi;
    }
    std::nth_element(ms.begin(), ms.begin() + static_cast<std::ptrdiff_t>(ms.size() / 2), ms.end());
    const double n = static_cast<double>(std::max<std::size_t>(pairs.size(), 1));
    j["methods"][m] = {
        {"ms_median", ms.empty() ? 0.0 : ms[ms.size() / 2]}, {"trans_err_m", et / n}, {"rot_err_deg", er / n}};
    if (!json)
      std::printf("%-10s %10.3f %14.4f %14.4f\n", m.c_str(), ms.empty() ? 0.0 : ms[ms.size() / 2], et / n, er / n);
  }
  if (json) std::cout << j.dump(2) << std::endl;
  return 0;
}

/// The scanning front-end's two paths on the consecutive scan pairs of an Oxford-layout sequence
/// (e.g. from radar_sim): points per scan, ms, and the error of scan-to-scan WeightedNDT2D (paper
/// defaults g = 3.75 m, s = 0.333) from a constant-velocity guess (the previous ground-truth
/// motion), against the ground truth of gt/radar_odometry.csv.
int benchScanningFrontEnds(const std::string& dir, bool json) {
  const auto stamps = readOxfordTimestamps(dir + "/radar.timestamps");
  const auto gt = readOxfordRadarOdometry(dir + "/gt/radar_odometry.csv");
  if (stamps.size() < 3 || gt.size() + 1 != stamps.size())
    throw std::invalid_argument(dir +
                                ": needs at least 3 scans and one gt/radar_odometry.csv row per consecutive pair");
  auto truth = [&](std::size_t k) { return Pose2(gt[k].x, -gt[k].y, -gt[k].yaw); };  // Oxford axes → vehicle
  nlohmann::json j;
  j["pairs"] = stamps.size() - 2;
  if (!json)
    std::printf(
        "radar_ndt_bench --oxford: %zu scan pairs of %s, WeightedNDT2D g = 3.75 m, s = 0.333, constant-velocity guess\n"
        "%-10s %12s %14s %10s %14s %14s\n",
        stamps.size() - 2, dir.c_str(), "front-end", "points/scan", "front-end ms", "match ms", "trans err m",
        "rot err deg");
  for (const bool cartesian : {true, false}) {
    PowerThresholdOptions o;
    o.cartesian = cartesian;
    const PowerThreshold front(o);
    std::vector<double> points, ms_front, ms_match;
    double et = 0, er = 0;
    pcl::PointCloud<PointRadar>::Ptr previous;
    for (std::size_t k = 0; k < stamps.size(); ++k) {
      const PolarScan scan = readOxfordPolarPng(dir + "/radar/" + std::to_string(stamps[k].stamp) + ".png");
      pcl::PointCloud<PointRadar>::Ptr cloud(new pcl::PointCloud<PointRadar>);
      const auto t0 = std::chrono::steady_clock::now();
      front.compute(scan, *cloud);
      ms_front.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      points.push_back(static_cast<double>(cloud->size()));
      if (k >= 2) {
        WeightedNDT2D<PointRadar, PointRadar> ndt;
        ndt.setResolution(3.75f);
        ndt.setPowerShift(0.333f);
        pcl::PointCloud<PointRadar> out;
        const auto t1 = std::chrono::steady_clock::now();
        ndt.setInputTarget(previous);
        ndt.setInputSource(cloud);
        ndt.align(out, toMatrix4<float>(truth(k - 2)));
        ms_match.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count());
        const Pose2 e = between(truth(k - 1), toPose2(ndt.getFinalTransformation()));
        et += e.head<2>().norm();
        er += std::abs(e.z()) * 180.0 / kPi;
      }
      previous = cloud;
    }
    auto median = [](std::vector<double> v) {
      std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
      return v[v.size() / 2];
    };
    const double n = static_cast<double>(stamps.size() - 2);
    const char* name = cartesian ? "cartesian" : "polar";
    j["front_ends"][name] = {{"points_median", median(points)},
                             {"front_end_ms_median", median(ms_front)},
                             {"match_ms_median", median(ms_match)},
                             {"trans_err_m", et / n},
                             {"rot_err_deg", er / n}};
    if (!json)
      std::printf("%-10s %12.0f %14.2f %10.2f %14.4f %14.4f\n", name, median(points), median(ms_front),
                  median(ms_match), et / n, er / n);
  }
  if (json) std::cout << j.dump(2) << std::endl;
  return 0;
}

int main(int argc, char** argv) {
  std::size_t pairs = 24, repeats = 1, nuscenes_stride = 5;
  std::string nuscenes_root, oxford_dir;
  std::string sizes_text;
  double grid = 3.0, shift = 0.3, noise = 0.05, clutter = 0.15, max_t = 2.0, max_r = 3.0, icp_dist = 5.0;
  bool json = false, with_icp = true, with_ndt2d = true;
  std::uint32_t seed = 1;
  po::options_description opts("Options");
  // clang-format off
  opts.add_options()
    ("help,h", "print this help and exit")
    ("pairs", po::value(&pairs)->default_value(24), "scan pairs (sizes cycle through --sizes)")
    ("sizes", po::value(&sizes_text)->default_value("5000,10000,20000"), "points per scan, comma-separated")
    ("repeats", po::value(&repeats)->default_value(1), "time each pair this many times (median kept)")
    ("seed", po::value(&seed)->default_value(1), "first seed; pair k uses seed + k")
    ("grid", po::value(&grid)->default_value(3.0), "grid size g (m) for WeightedNDT2D and PCL's NDT resolution")
    ("shift", po::value(&shift)->default_value(0.3, "0.3"), "WeightedNDT2D power shift s (clutter power is 0.02..0.3)")
    ("noise", po::value(&noise)->default_value(0.05, "0.05"), "position noise of the scans (m)")
    ("clutter", po::value(&clutter)->default_value(0.15, "0.15"), "fraction of low-power clutter points")
    ("max-translation", po::value(&max_t)->default_value(2.0), "true transforms up to this translation (m)")
    ("max-rotation", po::value(&max_r)->default_value(3.0), "and this rotation (deg)")
    ("icp-distance", po::value(&icp_dist)->default_value(5.0), "ICP max correspondence distance (m)")
    ("no-icp", po::bool_switch(), "skip pcl::IterativeClosestPoint")
    ("no-ndt2d", po::bool_switch(), "skip pcl::NormalDistributionsTransform2D")
    ("variants", po::bool_switch(), "also run WeightedNDT2D with overlapping grids, and without the source voxel merge")
    ("nuscenes", po::value(&nuscenes_root),
     "instead: real N = 3 submap pairs from this nuScenes-layout dataroot (ours, PCL NDT, PCL ICP)")
    ("oxford", po::value(&oxford_dir),
     "instead: the scanning front-end's Cartesian and polar paths on the scan pairs of this Oxford-layout sequence "
     "(e.g. radar_sim's)")
    ("nuscenes-stride", po::value(&nuscenes_stride)->default_value(5), "with --nuscenes: every k-th cycle")
    ("json", po::bool_switch(&json),
     "print one JSON object: per method ms_median, trans_err_m, rot_err_deg, converged_frac");
  // clang-format on
  const std::string usage =
      "Usage: radar_ndt_bench [--pairs N] [--sizes 5000,10000,20000] [--json]\n"
      "Synthetic 2D radar-like scan pairs (walls, poles, arcs, low-power clutter, noise) with known\n"
      "transforms; every method aligns the same pairs from the identity. Time = setInputSource +\n"
      "setInputTarget + align, single thread.\n"
      "       radar_ndt_bench --nuscenes DIR | --oxford DIR   (real submap pairs | scanning front-ends)";
  po::variables_map vm;
  const int rc = apps::parseCommandLine(argc, argv, opts, usage, vm);
  if (rc >= 0) return rc;
  with_icp = !vm["no-icp"].as<bool>();
  with_ndt2d = !vm["no-ndt2d"].as<bool>();

  return apps::runGuarded("radar_ndt_bench", [&]() {
    if (!oxford_dir.empty()) return benchScanningFrontEnds(oxford_dir, json);
    if (!nuscenes_root.empty()) return benchNuScenes(nuscenes_root, std::max<std::size_t>(1, nuscenes_stride), json);
    std::vector<std::size_t> sizes;
    {
      std::stringstream ss(sizes_text);
      for (std::string w; std::getline(ss, w, ',');) sizes.push_back(std::stoul(w));
      if (sizes.empty()) throw std::invalid_argument("--sizes is empty");
    }
    pcl::console::setVerbosityLevel(pcl::console::L_ERROR);

    std::vector<BenchMethod> methods;
    char buf[256];
    std::snprintf(buf, sizeof(buf),
                  "g=%.2f m, s=%.2f, neighbour-cell lookup, source voxel 0.25 m, max 35 it, eps 1e-6 m^2", grid, shift);
    // Ours with the benchmark's g and s; the variants change one setting each.
    const auto ours = [=](CellLookup lookup, double voxel) {
      return [=]() -> Reg::Ptr {
        auto r = pcl::make_shared<WeightedNDT2D<PointT, PointT>>();
        r->setResolution(static_cast<float>(grid));
        r->setPowerShift(static_cast<float>(shift));
        r->setCellLookup(lookup);
        r->setSourceVoxelSize(voxel);
        return r;
      };
    };
    const double default_voxel = WeightedNDT2D<PointT, PointT>().getSourceVoxelSize();
    methods.push_back({"radar_ndt::WeightedNDT2D", buf, ours(CellLookup::Neighbours, default_voxel)});
    std::snprintf(buf, sizeof(buf), "resolution=%.2f m, step 0.5, eps 1e-4, max 50 it", grid);
    methods.push_back({"pcl::NormalDistributionsTransform", buf, [=]() -> Reg::Ptr {
                         auto r = pcl::make_shared<pcl::NormalDistributionsTransform<PointT, PointT>>();
                         applyPclNdtSettings(*r, grid);
                         return r;
                       }});
    if (vm["variants"].as<bool>()) {
      std::snprintf(buf, sizeof(buf), "as above, Biber's four overlapping grids");
      methods.push_back({"WeightedNDT2D overlapping grids", buf, ours(CellLookup::OverlappingGrids, default_voxel)});
      std::snprintf(buf, sizeof(buf), "as above (neighbour cells), no source voxel merge");
      methods.push_back({"WeightedNDT2D no voxel merge", buf, ours(CellLookup::Neighbours, 0.0)});
    }
    if (with_ndt2d) {
      std::snprintf(buf, sizeof(buf), "grid step %.2f m, extent 130 m, centre 0, PCL defaults otherwise", grid);
      methods.push_back({"pcl::NormalDistributionsTransform2D", buf, [=]() -> Reg::Ptr {
                           auto r = pcl::make_shared<pcl::NormalDistributionsTransform2D<PointT, PointT>>();
                           r->setGridCentre(Eigen::Vector2f(0, 0));
                           r->setGridExtent(Eigen::Vector2f(130, 130));
                           r->setGridStep(Eigen::Vector2f(static_cast<float>(grid), static_cast<float>(grid)));
                           r->setMaximumIterations(50);
                           r->setTransformationEpsilon(1e-4);
                           return r;
                         }});
    }
    if (with_icp) {
      std::snprintf(buf, sizeof(buf), "max correspondence %.1f m, max 50 it, PCL defaults otherwise", icp_dist);
      methods.push_back({"pcl::IterativeClosestPoint", buf, [=]() -> Reg::Ptr {
                           auto r = pcl::make_shared<pcl::IterativeClosestPoint<PointT, PointT>>();
                           r->setMaxCorrespondenceDistance(icp_dist);
                           r->setMaximumIterations(MatcherOptions().icp_max_iterations);
                           return r;
                         }});
    }

    std::map<std::string, std::vector<Sample>> results;
    std::vector<double> kdtree_ms_10k;  // what pcl::Registration::align would pay for the target kd-tree
    std::size_t model_cells = 0, model_bytes = 0;
    for (std::size_t k = 0; k < pairs; ++k) {
      SyntheticScanOptions o;
      o.points = sizes[k % sizes.size()];
      o.seed = seed + static_cast<std::uint32_t>(k);
      o.noise_std = noise;
      o.clutter_fraction = clutter;
      o.max_translation = max_t;
      o.max_rotation_deg = max_r;
      const SyntheticScanPair pair = makeSyntheticScanPair(o);
      const Cloud::Ptr src = toXYZI(pair.source), tgt = toXYZI(pair.target);
      if (o.points == 10000) {
        pcl::search::KdTree<PointT> tree;
        const auto t0 = std::chrono::steady_clock::now();
        tree.setInputCloud(tgt);
        kdtree_ms_10k.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      }
      for (const auto& m : methods) {
        std::vector<double> times;
        Sample s{};
        for (std::size_t r = 0; r < std::max<std::size_t>(1, repeats); ++r) {
          Reg::Ptr reg = m.make();
          Cloud out;
          const auto t0 = std::chrono::steady_clock::now();
          reg->setInputSource(src);
          reg->setInputTarget(tgt);
          reg->align(out);
          const auto t1 = std::chrono::steady_clock::now();
          times.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
          const Pose2 est = toPose2(reg->getFinalTransformation());
          s.trans_err = (est.head<2>() - pair.source_in_target.head<2>()).norm();
          s.rot_err_deg = std::abs(normalizeAngle(est.z() - pair.source_in_target.z())) * 180.0 / kPi;
          s.converged = reg->hasConverged();
          if (k == 1 && r == 0) {
            if (auto* ours = dynamic_cast<WeightedNDT2D<PointT, PointT>*>(reg.get())) {
              model_cells = ours->getNumCells();
              model_bytes = ours->getTargetModelBytes();
            }
          }
        }
        s.ms = median(times);
        s.points = o.points;
        results[m.name].push_back(s);
      }
      if (!json) std::fprintf(stderr, "\rpair %zu/%zu", k + 1, pairs);
    }
    if (!json) std::fprintf(stderr, "\n");

    // Summaries.
    nlohmann::json j;
    const double ours_ms = [&] {
      std::vector<double> v;
      for (const auto& s : results[methods[0].name]) v.push_back(s.ms);
      return median(v);
    }();
    if (!json) {
      std::printf(
          "radar_ndt_bench: %zu pairs of %s points, noise %.2f m, clutter %.0f %%, transforms up to %.1f m "
          "and %.1f deg, identity guess, single thread\n\n",
          pairs, sizes_text.c_str(), noise, 100 * clutter, max_t, max_r);
      std::printf("%-36s %10s %10s %12s %12s %10s %9s\n", "method", "ms median", "ms @10k", "trans err m",
                  "rot err deg", "converged", "ours is");
    }
    for (const auto& m : methods) {
      const auto& v = results[m.name];
      std::vector<double> ms, ms10k;
      double te = 0, re = 0, conv = 0;
      for (const auto& s : v) {
        ms.push_back(s.ms);
        if (s.points == 10000) ms10k.push_back(s.ms);
        te += s.trans_err;
        re += s.rot_err_deg;
        conv += s.converged ? 1 : 0;
      }
      const double n = static_cast<double>(v.size());
      const double med = median(ms);
      j["methods"][m.name] = {{"ms_median", med},           {"ms_median_10k", ms10k.empty() ? 0.0 : median(ms10k)},
                              {"trans_err_m", te / n},      {"rot_err_deg", re / n},
                              {"converged_frac", conv / n}, {"speed_ratio_ours", med / ours_ms},
                              {"settings", m.settings}};
      if (!json) {
        char ratio[32] = "";
        if (&m != &methods[0]) std::snprintf(ratio, sizeof(ratio), "%.1fx", med / ours_ms);
        std::printf("%-36s %10.2f %10.2f %12.4f %12.4f %9.0f%% %9s\n", m.name.c_str(), med,
                    ms10k.empty() ? 0.0 : median(ms10k), te / n, re / n, 100 * conv / n, ratio);
      }
    }
    j["pairs"] = pairs;
    j["sizes"] = sizes;
    j["target_model"] = {{"cells", model_cells}, {"bytes", model_bytes}};
    j["pcl_target_kdtree_ms_10k"] = median(kdtree_ms_10k);
    if (json) {
      std::cout << j.dump(2) << std::endl;
    } else {
      std::printf(
          "\n(trans/rot err: mean over pairs against the known transform; 'ours is': how many times faster"
          " WeightedNDT2D is)\n\nSettings:\n");
      for (const auto& m : methods) std::printf("  %-36s %s\n", m.name.c_str(), m.settings.c_str());
      std::printf("WeightedNDT2D target model of a 10k-point scan: %zu cells, %.1f KiB\n", model_cells,
                  static_cast<double>(model_bytes) / 1024.0);
      std::printf(
          "PCL target kd-tree of a 10k-point scan (built by every pcl::Registration::align, not by ours):"
          " %.2f ms median\n",
          median(kdtree_ms_10k));
    }
    return 0;
  });
}

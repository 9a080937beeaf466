// radar_ndt_bench's synthetic benchmark (ndt_bench/ndt_bench.h): WeightedNDT2D against PCL's NDT, NDT2D
// and ICP on the same synthetic radar-like scan pairs with known transforms (identity initial
// guess), single thread. Time = setInputSource + setInputTarget + align.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>
#include <map>

#include <nlohmann/json.hpp>
#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>
#include <pcl/registration/ndt_2d.h>

#include "app_common.h"
#include "ndt_bench/ndt_bench.h"
#include "radar_ndt/odometry/matcher.h"
#include "radar_ndt/registration/weighted_ndt_2d.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/sim/synthetic_scan.h"

namespace radar_ndt {
namespace apps {

namespace {

using PointT = pcl::PointXYZI;  // every method sees the same clouds; intensity = power
using Cloud = pcl::PointCloud<PointT>;
using Reg = pcl::Registration<PointT, PointT>;

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

/// The methods every pair is aligned with: WeightedNDT2D at the benchmark's g and s (and, with
/// variants, one setting changed each), PCL's NDT, NDT2D and ICP.
std::vector<BenchMethod> engines(const SyntheticBench& b) {
  std::vector<BenchMethod> methods;
  char buf[256];
  const double grid = b.grid, shift = b.shift, icp_dist = b.icp_dist;
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
  if (b.variants) {
    std::snprintf(buf, sizeof(buf), "as above, Biber's four overlapping grids");
    methods.push_back({"WeightedNDT2D overlapping grids", buf, ours(CellLookup::OverlappingGrids, default_voxel)});
    std::snprintf(buf, sizeof(buf), "as above (neighbour cells), no source voxel merge");
    methods.push_back({"WeightedNDT2D no voxel merge", buf, ours(CellLookup::Neighbours, 0.0)});
  }
  if (b.with_ndt2d) {
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
  if (b.with_icp) {
    std::snprintf(buf, sizeof(buf), "max correspondence %.1f m, max 50 it, PCL defaults otherwise", icp_dist);
    methods.push_back({"pcl::IterativeClosestPoint", buf, [=]() -> Reg::Ptr {
                         auto r = pcl::make_shared<pcl::IterativeClosestPoint<PointT, PointT>>();
                         r->setMaxCorrespondenceDistance(icp_dist);
                         r->setMaximumIterations(MatcherOptions().icp_max_iterations);
                         return r;
                       }});
  }

  return methods;
}

/// What every method measured on every pair.
struct Measured {
  std::map<std::string, std::vector<Sample>> results;
  std::vector<double> kdtree_ms_10k;  // what pcl::Registration::align would pay for the target kd-tree
  std::size_t model_cells = 0, model_bytes = 0;
};

/// Pair k, its 10k-point target's kd-tree time, and each method's median time and errors on it.
void measurePair(const SyntheticBench& b, const std::vector<BenchMethod>& methods, std::size_t k, Measured& m) {
  SyntheticScanOptions o;
  o.points = b.sizes[k % b.sizes.size()];
  o.seed = b.seed + static_cast<std::uint32_t>(k);
  o.noise_std = b.noise;
  o.clutter_fraction = b.clutter;
  o.max_translation = b.max_t;
  o.max_rotation_deg = b.max_r;
  const SyntheticScanPair pair = makeSyntheticScanPair(o);
  const Cloud::Ptr src = toXYZI(pair.source), tgt = toXYZI(pair.target);
  if (o.points == 10000) {
    pcl::search::KdTree<PointT> tree;
    const auto t0 = std::chrono::steady_clock::now();
    tree.setInputCloud(tgt);
    m.kdtree_ms_10k.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  for (const auto& method : methods) {
    std::vector<double> times;
    Sample s{};
    for (std::size_t r = 0; r < std::max<std::size_t>(1, b.repeats); ++r) {
      Reg::Ptr reg = method.make();
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
      if (k == 1 && r == 0)
        if (auto* ndt = dynamic_cast<WeightedNDT2D<PointT, PointT>*>(reg.get())) {
          m.model_cells = ndt->getNumCells();
          m.model_bytes = ndt->getTargetModelBytes();
        }
    }
    s.ms = median(times);
    s.points = o.points;
    m.results[method.name].push_back(s);
  }
}

/// Each method's summary row (printed, and into `j`); WeightedNDT2D, the first, is what the
/// speed ratios are against.
void summarize(const SyntheticBench& b, const std::vector<BenchMethod>& methods, Measured& m, nlohmann::json& j) {
  std::vector<double> first;
  for (const auto& s : m.results[methods[0].name]) first.push_back(s.ms);
  const double ours_ms = median(first);
  for (const auto& method : methods) {
    const auto& v = m.results[method.name];
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
    j["methods"][method.name] = {{"ms_median", med},           {"ms_median_10k", ms10k.empty() ? 0.0 : median(ms10k)},
                                 {"trans_err_m", te / n},      {"rot_err_deg", re / n},
                                 {"converged_frac", conv / n}, {"speed_ratio_ours", med / ours_ms},
                                 {"settings", method.settings}};
    if (!b.json) {
      char ratio[32] = "";
      if (&method != &methods[0]) std::snprintf(ratio, sizeof(ratio), "%.1fx", med / ours_ms);
      std::printf("%-36s %10.2f %10.2f %12.4f %12.4f %9.0f%% %9s\n", method.name.c_str(), med,
                  ms10k.empty() ? 0.0 : median(ms10k), te / n, re / n, 100 * conv / n, ratio);
    }
  }
}

}  // namespace

int benchSynthetic(const SyntheticBench& b) {
  pcl::console::setVerbosityLevel(pcl::console::L_ERROR);
  const std::vector<BenchMethod> methods = engines(b);
  Measured m;
  for (std::size_t k = 0; k < b.pairs; ++k) {
    measurePair(b, methods, k, m);
    if (!b.json) std::fprintf(stderr, "\rpair %zu/%zu", k + 1, b.pairs);
  }
  if (!b.json) {
    std::fprintf(stderr, "\n");
    std::printf(
        "radar_ndt_bench: %zu pairs of %s points, noise %.2f m, clutter %.0f %%, transforms up to %.1f m "
        "and %.1f deg, identity guess, single thread\n\n",
        b.pairs, b.sizes_text.c_str(), b.noise, 100 * b.clutter, b.max_t, b.max_r);
    std::printf("%-36s %10s %10s %12s %12s %10s %9s\n", "method", "ms median", "ms @10k", "trans err m", "rot err deg",
                "converged", "ours is");
  }
  nlohmann::json j;
  summarize(b, methods, m, j);
  j["pairs"] = b.pairs;
  j["sizes"] = b.sizes;
  j["target_model"] = {{"cells", m.model_cells}, {"bytes", m.model_bytes}};
  j["pcl_target_kdtree_ms_10k"] = median(m.kdtree_ms_10k);
  if (b.json) {
    std::cout << j.dump(2) << std::endl;
    return 0;
  }
  std::printf(
      "\n(trans/rot err: mean over pairs against the known transform; 'ours is': how many times faster"
      " WeightedNDT2D is)\n\nSettings:\n");
  for (const auto& method : methods) std::printf("  %-36s %s\n", method.name.c_str(), method.settings.c_str());
  std::printf("WeightedNDT2D target model of a 10k-point scan: %zu cells, %.1f KiB\n", m.model_cells,
              static_cast<double>(m.model_bytes) / 1024.0);
  std::printf(
      "PCL target kd-tree of a 10k-point scan (built by every pcl::Registration::align, not by ours):"
      " %.2f ms median\n",
      median(m.kdtree_ms_10k));
  return 0;
}

}  // namespace apps
}  // namespace radar_ndt

// radar_ndt_bench on real data (ndt_bench/ndt_bench.h): the registered matchers on nuScenes submap
// pairs, and the scanning front-end's two paths on an Oxford-layout sequence.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>

#include <nlohmann/json.hpp>

#include "ndt_bench/ndt_bench.h"
#include "radar_ndt/frontend/automotive_front_end.h"
#include "radar_ndt/frontend/power_threshold.h"
#include "radar_ndt/frontend/probabilistic_submap.h"
#include "radar_ndt/io/nuscenes_sequence.h"
#include "radar_ndt/io/oxford_ground_truth.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/odometry/matcher_registry.h"
#include "radar_ndt/registration/weighted_ndt_2d.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/statistics.h"

namespace radar_ndt {
namespace apps {

/// Real submap pairs: N = 3 probabilistic submaps of consecutive cycles of every scene under
/// `dataroot` (every `stride`-th cycle), each method started from the Doppler integral; errors
/// against the ground-truth motion between the two cycles.
namespace {

struct SubmapPair {
  pcl::PointCloud<PointRadar>::Ptr source, target;
  Pose2 guess, truth;
};

/// Every `stride`-th cycle's submap (N = 3) with the one before, the Doppler motion and the truth.
std::vector<SubmapPair> submapPairs(const std::string& dataroot, std::size_t stride) {
  const NuScenesDataset ds(dataroot);
  const AutomotiveFrontEnd fe;
  std::vector<SubmapPair> pairs;
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
  return pairs;
}

}  // namespace

int benchNuScenes(const std::string& dataroot, std::size_t stride, bool json) {
  const std::vector<SubmapPair> pairs = submapPairs(dataroot, stride);
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
    if (uses.automotiveOnly() || uses.doppler_weights) continue;
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
    const double n = static_cast<double>(std::max<std::size_t>(pairs.size(), 1));
    j["methods"][m] = {{"ms_median", median(ms)}, {"trans_err_m", et / n}, {"rot_err_deg", er / n}};
    if (!json) std::printf("%-10s %10.3f %14.4f %14.4f\n", m.c_str(), median(ms), et / n, er / n);
  }
  if (json) std::cout << j.dump(2) << std::endl;
  return 0;
}

namespace {

/// One front-end's figures over the sequence's scan pairs.
struct FrontEndFigures {
  std::vector<double> points, ms_front, ms_match;
  double et = 0, er = 0;
};

FrontEndFigures frontEndFigures(const std::string& dir, const std::vector<OxfordStamp>& stamps,
                                const std::function<Pose2(std::size_t)>& truth, bool cartesian) {
  PowerThresholdOptions o;
  o.cartesian = cartesian;
  const PowerThreshold front(o);
  FrontEndFigures f;
  pcl::PointCloud<PointRadar>::Ptr previous;
  for (std::size_t k = 0; k < stamps.size(); ++k) {
    const PolarScan scan = readOxfordPolarPng(dir + "/radar/" + std::to_string(stamps[k].stamp) + ".png");
    pcl::PointCloud<PointRadar>::Ptr cloud(new pcl::PointCloud<PointRadar>);
    const auto t0 = std::chrono::steady_clock::now();
    front.compute(scan, *cloud);
    f.ms_front.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    f.points.push_back(static_cast<double>(cloud->size()));
    if (k >= 2) {
      WeightedNDT2D<PointRadar, PointRadar> ndt;
      ndt.setResolution(3.75f);
      ndt.setPowerShift(0.333f);
      pcl::PointCloud<PointRadar> out;
      const auto t1 = std::chrono::steady_clock::now();
      ndt.setInputTarget(previous);
      ndt.setInputSource(cloud);
      ndt.align(out, toMatrix4<float>(truth(k - 2)));
      f.ms_match.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count());
      const Pose2 e = between(truth(k - 1), toPose2(ndt.getFinalTransformation()));
      f.et += e.head<2>().norm();
      f.er += std::abs(e.z()) * 180.0 / kPi;
    }
    previous = cloud;
  }
  return f;
}

}  // namespace

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
  const std::function<Pose2(std::size_t)> truth = [&](std::size_t k) {
    return Pose2(gt[k].x, -gt[k].y, -gt[k].yaw);  // Oxford axes → vehicle
  };
  nlohmann::json j;
  j["pairs"] = stamps.size() - 2;
  if (!json)
    std::printf(
        "radar_ndt_bench --oxford: %zu scan pairs of %s, WeightedNDT2D g = 3.75 m, s = 0.333, constant-velocity guess\n"
        "%-10s %12s %14s %10s %14s %14s\n",
        stamps.size() - 2, dir.c_str(), "front-end", "points/scan", "front-end ms", "match ms", "trans err m",
        "rot err deg");
  for (const bool cartesian : {true, false}) {
    const FrontEndFigures f = frontEndFigures(dir, stamps, truth, cartesian);
    const double n = static_cast<double>(stamps.size() - 2);
    const char* name = cartesian ? "cartesian" : "polar";
    j["front_ends"][name] = {{"points_median", median(f.points)},
                             {"front_end_ms_median", median(f.ms_front)},
                             {"match_ms_median", median(f.ms_match)},
                             {"trans_err_m", f.et / n},
                             {"rot_err_deg", f.er / n}};
    if (!json)
      std::printf("%-10s %12.0f %14.2f %10.2f %14.4f %14.4f\n", name, median(f.points), median(f.ms_front),
                  median(f.ms_match), f.et / n, f.er / n);
  }
  if (json) std::cout << j.dump(2) << std::endl;
  return 0;
}

}  // namespace apps
}  // namespace radar_ndt

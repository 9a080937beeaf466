// radar_ndt3d_bench: the 3D matchers of the registry (radar_ndt/odometry/matcher_registry_3d.h:
// WeightedNDT3D, PCL's 3D NDT and GICP) on the same simulated 4D radar scan-to-map pairs
// (radar_ndt/sim/radar_4d.h), each from a guess off by a given translation and rotation in random
// directions. Per preset and method: how often the true pose is recovered, the median errors,
// iterations and time (setInputSource + setInputTarget + align, single thread), and each method's
// time over the first's (ours) on the same pairs.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <boost/program_options.hpp>
#include <nlohmann/json.hpp>

#include "radar_ndt/odometry/matcher_registry_3d.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/sim/radar_4d.h"
#include "radar_ndt/statistics.h"

using namespace radar_ndt;
namespace po = boost::program_options;

namespace {

struct Bench {
  std::vector<std::string> presets, methods;
  Matcher3DOptions settings;
  int pairs = 20;
  std::uint64_t seed = 1;
  double translation_error = 1.0, rotation_error_deg = 5.0;
  double success_translation = 0.3, success_rotation_deg = 1.0;
  bool json = false;
};

/// One method's outcome on one pair.
struct Outcome {
  double t_err, r_err_deg, ms;
  int iterations;
  bool success;
};

using Cloud = pcl::PointCloud<PointRadar4D>;

/// Runs `reg` on the pair and scores it against the truth.
Outcome run(const Matcher3DEntry& entry, Registration3D& reg, const Cloud::Ptr& source, const Cloud::Ptr& target,
            const sim::ScanToMapPair& pair, const Bench& b) {
  Cloud aligned;
  const auto t0 = std::chrono::steady_clock::now();
  reg.setInputSource(source);
  reg.setInputTarget(target);
  reg.align(aligned, toMatrix4<float>(pair.guess));
  const auto t1 = std::chrono::steady_clock::now();
  const Pose3 est = toPose3(reg.getFinalTransformation());
  const Pose3 err = pair.truth.inverse() * est;
  Outcome o;
  o.t_err = err.translation().norm();
  o.r_err_deg = Eigen::AngleAxisd(err.linear()).angle() * 180.0 / kPi;
  o.ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  o.iterations = entry.iterations(reg);
  o.success = o.t_err < b.success_translation && o.r_err_deg < b.success_rotation_deg;
  return o;
}

struct MethodRows {
  std::string name;
  std::vector<Outcome> rows;
};

/// Every method on every pair of one preset, in --methods' order.
std::vector<MethodRows> runPreset(const std::string& preset, const Bench& b) {
  sim::ScanToMapOptions o;
  o.preset = preset;
  o.translation_error = b.translation_error;
  o.rotation_error = b.rotation_error_deg * kPi / 180.0;
  o.map_scans = preset == "ti_iwr6843_rio" ? 10 : 5;
  // One instance a method for all pairs, as an odometry keeps its matcher from scan to scan.
  std::vector<MethodRows> m;
  std::vector<std::shared_ptr<Registration3D>> matchers;
  for (const std::string& name : b.methods) {
    m.push_back({name, {}});
    matchers.push_back(findMatcher3D(name).make(b.settings));
  }
  for (int k = 0; k < b.pairs; ++k) {
    const sim::ScanToMapPair pair = sim::scanToMapPair(o, b.seed, k);
    const Cloud::Ptr src(new Cloud(pair.source)), map(new Cloud(pair.map));
    for (std::size_t i = 0; i < matchers.size(); ++i)
      m[i].rows.push_back(run(findMatcher3D(b.methods[i]), *matchers[i], src, map, pair, b));
  }
  return m;
}

double medianOf(const std::vector<Outcome>& rows, double Outcome::*field) {
  std::vector<double> v;
  for (const auto& r : rows) v.push_back(r.*field);
  return median(v);
}

nlohmann::json summarise(const std::vector<MethodRows>& methods) {
  nlohmann::json out = nlohmann::json::array();
  const double ours_ms = medianOf(methods[0].rows, &Outcome::ms);
  for (const auto& m : methods) {
    std::size_t ok = 0;
    std::vector<double> it;
    for (const auto& r : m.rows) {
      ok += r.success ? 1 : 0;
      it.push_back(r.iterations);
    }
    const double ms = medianOf(m.rows, &Outcome::ms);
    out.push_back({{"method", m.name},
                   {"recovered", static_cast<double>(ok) / static_cast<double>(m.rows.size())},
                   {"trans_err_m", medianOf(m.rows, &Outcome::t_err)},
                   {"rot_err_deg", medianOf(m.rows, &Outcome::r_err_deg)},
                   {"iterations", median(it)},
                   {"ms_median", ms},
                   {"time_over_ours", ms / ours_ms}});
  }
  return out;
}

/// The markdown table of docs/results/matcher_3d.md.
void printTable(const Bench& b, const nlohmann::json& all) {
  std::cout << "| preset | method | recovered | median trans. err (m) | median rot. err (deg) | iterations | ms | "
               "time / ours |\n"
               "|---|---|---|---|---|---|---|---|\n";
  for (const auto& p : b.presets)
    for (const auto& r : all[p])
      std::cout << std::fixed << std::setprecision(3) << "| " << p << " | " << r["method"].get<std::string>() << " | "
                << r["recovered"].get<double>() << " | " << r["trans_err_m"].get<double>() << " | "
                << r["rot_err_deg"].get<double>() << " | " << std::setprecision(1) << r["iterations"].get<double>()
                << " | " << std::setprecision(2) << r["ms_median"].get<double>() << " | "
                << r["time_over_ours"].get<double>() << " |\n";
}

}  // namespace

int main(int argc, char** argv) {
  Bench b;
  std::string presets = "ti_iwr6843_rio,ars548,oculii_eagle", methods = "pw-ndt-3d,pcl-ndt-3d,pcl-gicp";
  Matcher3DOptions& s = b.settings;
  po::options_description o("Options");
  // clang-format off
  o.add_options()
    ("help,h", "print this help and exit")
    ("presets", po::value(&presets)->default_value(presets), "4D radar presets, comma-separated")
    ("methods", po::value(&methods)->default_value(methods),
     "3D matchers of the registry, comma-separated; the first is the one the others' times are over")
    ("pairs", po::value(&b.pairs)->default_value(b.pairs), "scan-to-map pairs a preset")
    ("seed", po::value(&b.seed)->default_value(b.seed), "the world's and the scans' seed")
    ("translation-error", po::value(&b.translation_error)->default_value(1.0, "1"), "the guess's translation error (m)")
    ("rotation-error", po::value(&b.rotation_error_deg)->default_value(5.0, "5"), "the guess's rotation error (deg)")
    ("pcl-ndt-resolution", po::value(&s.pcl_ndt_resolution)->default_value(2.0, "2"), "PCL NDT's cell size (m)")
    ("pcl-ndt-step", po::value(&s.pcl_ndt_step)->default_value(0.5, "0.5"), "PCL NDT's line search's largest step (m)")
    ("pcl-ndt-epsilon", po::value(&s.pcl_ndt_epsilon)->default_value(0.01, "0.01"),
     "PCL NDT's transformation epsilon (PCL's tutorial's 0.01; its default, 0.1, stops after one step of 0.1 m)")
    ("gicp-distance", po::value(&s.gicp_max_correspondence)->default_value(3.0, "3"), "GICP's max correspondence distance (m)")
    ("success-translation", po::value(&b.success_translation)->default_value(0.3, "0.3"), "recovered: within this (m) ...")
    ("success-rotation", po::value(&b.success_rotation_deg)->default_value(1.0, "1"), "... and this (deg) of the truth")
    ("json", po::bool_switch(&b.json), "print one JSON object per preset and method");
  // clang-format on
  try {
    po::variables_map vm;
    po::store(po::parse_command_line(argc, argv, o), vm);
    if (vm.count("help")) {
      std::cout << "Usage: radar_ndt3d_bench [--presets P,...] [--methods M,...] [--pairs N] [--json]\n"
                   "Simulated 4D radar scan-to-map pairs (radar_ndt/sim/radar_4d.h): the registry's 3D matchers\n"
                   "(pw-ndt-3d: WeightedNDT3D, pcl-ndt-3d, pcl-gicp) from the same guess, single thread.\n"
                   "docs/results/matcher_3d.md.\n\n"
                << o;
      return 0;
    }
    po::notify(vm);
    std::stringstream ss(presets);
    for (std::string p; std::getline(ss, p, ',');) b.presets.push_back(p);
    std::stringstream sm(methods);
    for (std::string m; std::getline(sm, m, ',');) b.methods.push_back(findMatcher3D(m).name);
    if (b.methods.empty()) throw std::invalid_argument("--methods names no matcher");
    s.validate();
    nlohmann::json all;
    for (const auto& p : b.presets) all[p] = summarise(runPreset(p, b));
    if (b.json) {
      std::cout << all.dump(2) << "\n";
      return 0;
    }
    printTable(b, all);
  } catch (const std::exception& e) {
    std::cerr << "radar_ndt3d_bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

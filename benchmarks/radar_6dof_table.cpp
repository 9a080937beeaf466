// radar_6dof_table: the 6-DoF accuracy table on the 4D simulator driven by real motion. Each real
// trajectory (hand-held TUM files with the TI preset, a Boreas pose file with the car presets)
// becomes a smooth motion (radar_ndt/sim/motion_6dof.h); a world is built around its path; the
// radar's scans and a 6-axis IMU are simulated along it; each method runs on them and is scored
// against the motion with the 6-DoF metrics (rpg's ATE after position + yaw alignment, its
// relative error, the final position error). Today's method: the doppler-imu baseline; part 2's
// odometry adds its rows beside it.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <boost/program_options.hpp>

#include "radar_ndt/evaluation/metrics.h"
#include "radar_ndt/evaluation/metrics_6dof.h"
#include "radar_ndt/frontend/ego_velocity_3d.h"
#include "radar_ndt/io/boreas_ground_truth.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/odometry/doppler_imu.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/sim/motion_6dof.h"
#ifdef RADAR_NDT_WITH_ROS
#include "radar_ndt/ros/rosbag_sequence.h"
#endif

using namespace radar_ndt;
namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

struct Case {
  std::string driver, preset, imu;
  Trajectory trajectory;
  bool car = false;
  double rate = 10;
  std::vector<double> distances;
};

/// The first `seconds` of `t` (all of it when `seconds` <= 0).
Trajectory firstSeconds(Trajectory t, double seconds) {
  if (seconds <= 0) return t;
  const double end = t.stamps.front() + seconds;
  while (t.size() > 4 && t.stamps.back() > end) {
    t.stamps.pop_back();
    t.poses.pop_back();
  }
  return t;
}

std::string fmt(double v, const char* f = "%.2f") {
  if (!std::isfinite(v)) return "n/a";
  char b[32];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

/// 5th / 50th / 95th percentiles of `x`, "a / b / c".
std::string percentiles(std::vector<double> x, const char* f) {
  if (x.empty()) return "n/a";
  std::sort(x.begin(), x.end());
  auto q = [&](double p) { return fmt(x[static_cast<std::size_t>(p * static_cast<double>(x.size() - 1))], f); };
  return q(0.05) + " / " + q(0.5) + " / " + q(0.95);
}

/// The scans' statistics as docs/simulator.md gives the real TI bag's: detections a scan, range,
/// azimuth and elevation (degrees), Doppler.
std::string scanStatistics(const Case& c, const sim::Radar4DSequence& seq) {
  std::vector<double> counts, range, azimuth, elevation, doppler;
  for (const auto& scan : seq.scans) {
    counts.push_back(static_cast<double>(scan.size()));
    for (const PointRadar4D& p : scan) {
      const double r = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
      range.push_back(r);
      azimuth.push_back(std::atan2(p.y, p.x) * 180 / kPi);
      elevation.push_back(std::asin(p.z / r) * 180 / kPi);
      doppler.push_back(p.doppler);
    }
  }
  return "| " + c.driver + " | " + c.preset + " | " + percentiles(counts, "%.0f") + " | " + percentiles(range, "%.1f") +
         " | " + percentiles(azimuth, "%.0f") + " | " + percentiles(elevation, "%.0f") + " | " +
         percentiles(doppler, "%.2f") + " |";
}

std::vector<std::string> statistics_rows;

/// The range bands the TI preset is calibrated in (m).
const std::vector<double> kBands = {0.5, 2, 4, 8, 20};

/// Per range band: detections a scan, elevation (deg), power, and |Doppler residual| (m/s) against
/// the scan's own 3D ego-velocity (valid scans only), as rows "| source | band | ... |".
std::string bandRows(const std::string& source, const std::vector<pcl::PointCloud<PointRadar4D>>& scans) {
  const EgoVelocity3DEstimator estimator;
  std::string out;
  for (std::size_t b = 0; b + 1 < kBands.size(); ++b) {
    std::vector<double> elevation, power, residual;
    for (const auto& scan : scans) {
      const EgoVelocity3D e = estimator.estimate(scan);
      for (const PointRadar4D& p : scan) {
        const Eigen::Vector3d q(p.x, p.y, p.z);
        const double r = q.norm();
        if (!(r >= kBands[b] && r < kBands[b + 1])) continue;
        elevation.push_back(std::asin(p.z / r) * 180 / kPi);
        power.push_back(p.power);
        if (e.valid) residual.push_back(std::abs(p.doppler - predictedDoppler3D(q, e.velocity)));
      }
    }
    const double per_scan =
        static_cast<double>(elevation.size()) / static_cast<double>(std::max<std::size_t>(1, scans.size()));
    out += "| " + source + " | " + fmt(kBands[b], "%.1f") + "–" + fmt(kBands[b + 1], "%.0f") + " | " +
           fmt(per_scan, "%.1f") + " | " + percentiles(elevation, "%.0f") + " | " + percentiles(power, "%.1f") + " | " +
           percentiles(residual, "%.2f") + " |\n";
  }
  return out;
}

/// The real rio bag's scans (the TI driver's intensity as the power), radar frame.
std::vector<pcl::PointCloud<PointRadar4D>> rioScans(const std::string& bag) {
  std::vector<pcl::PointCloud<PointRadar4D>> scans;
#ifdef RADAR_NDT_WITH_ROS
  SensorDescription d = readSensorDescription("preset:ti_iwr6843_rio");
  d.radars[0].fields.power = "intensity";
  const ros1::RosbagRadarSequence seq(bag, d);
  for (std::size_t k = 0; k < seq.size(); ++k) {
    const RadarCycle c = seq.load(k);
    pcl::PointCloud<PointRadar4D> scan;
    for (const auto& sweep : c.sweeps)
      for (const PointRadar& p : sweep.points) {
        PointRadar4D q(p.x, p.y, p.z, p.power);
        q.doppler = p.doppler;
        scan.push_back(q);
      }
    scans.push_back(scan);
  }
#else
  throw std::invalid_argument("--rio-bag " + bag + ": built without ROS");
#endif
  return scans;
}

/// The TI preset along a hand-held case at the rig's own mounting (the preset description's), for
/// the comparison per range band with the real bag.
std::string tiBandRows(const Case& c, std::uint64_t seed) {
  const sim::Motion6Dof motion(c.trajectory);
  const SensorDescription d = readSensorDescription("preset:ti_iwr6843_rio");
  const sim::Radar4DSequence seq =
      sim::simulateRadar4DSequence(motion, sim::worldAlongPath(motion, false, seed), sim::radar4DPreset(c.preset),
                                   c.rate, sim::imu6Preset("none"), seed, d.radars[0].mounting->transform());
  return bandRows("simulated, " + c.driver, seq.scans);
}

void runCase(const Case& c, std::uint64_t seed, const std::string& write_dir) {
  const auto t0 = std::chrono::steady_clock::now();
  const sim::Motion6Dof motion(c.trajectory);
  const sim::World3D world = sim::worldAlongPath(motion, c.car, seed);
  const sim::Radar4DSequence seq =
      sim::simulateRadar4DSequence(motion, world, sim::radar4DPreset(c.preset), c.rate, sim::imu6Preset(c.imu), seed);
  if (c.imu == "mems") statistics_rows.push_back(scanStatistics(c, seq));
  // doppler-imu: each scan's 3D Doppler velocity (the radar at the body's origin), the IMU.
  const EgoVelocity3DEstimator estimator;
  std::vector<BodyVelocitySample> velocities;
  std::size_t valid = 0;
  std::vector<double> velocity_errors;
  for (std::size_t k = 0; k < seq.scans.size(); ++k) {
    const EgoVelocity3D e = estimator.estimate(seq.scans[k]);
    velocities.push_back({seq.stamps[k], e.velocity, e.valid});
    valid += e.valid;
    if (e.valid)
      velocity_errors.push_back(
          (e.velocity - seq.truth.poses[k].linear().transpose() * motion.velocity(seq.stamps[k])).norm());
  }
  std::sort(velocity_errors.begin(), velocity_errors.end());
  const double velocity_error = velocity_errors.empty() ? NAN : velocity_errors[velocity_errors.size() / 2];
  const DopplerImuResult r = runDopplerImu(seq.imu, velocities);
  const PosePairs pairs = associate(seq.truth, r.trajectory);
  const AbsoluteError6Dof ate = absoluteTrajectoryError6Dof(pairs, TrajectoryAlignment::PositionYaw);
  const FinalError final_error = finalPositionError(pairs);
  std::string re;
  for (double d : c.distances) {
    const RelativeError e = relativeError(pairs, d);
    re += " " + fmt(e.trans_mean_pct) + " / " + fmt(e.yaw_mean_deg) + " |";
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("| %s | %s | %s | %.0f | %zu | %zu | %s | %s | %s |%s %s | %.0f |\n", c.driver.c_str(), c.preset.c_str(),
              c.imu.c_str(), motion.length(), seq.scans.size(), valid, fmt(velocity_error, "%.3f").c_str(),
              fmt(ate.rmse_m).c_str(), fmt(ate.rot_rmse_deg).c_str(), re.c_str(), fmt(final_error.final_pct).c_str(),
              seconds);
  for (const auto& p : r.problems) std::fprintf(stderr, "%s %s: %s\n", c.driver.c_str(), c.preset.c_str(), p.c_str());
  if (!write_dir.empty()) {
    const std::string stem = write_dir + "/" + c.driver + "_" + c.preset + "_" + c.imu;
    writeTum(stem + "_truth.tum", seq.truth);
    writeTum(stem + "_doppler_imu.tum", r.trajectory);
  }
}

/// The cases: each hand-held file with the TI preset and a MEMS IMU; the Boreas drive with both
/// car presets and both IMU grades.
std::vector<Case> buildCases(const std::vector<std::string>& handheld, const std::string& boreas, double seconds) {
  std::vector<Case> cases;
  for (const std::string& f : handheld)
    cases.push_back({fs::path(f).stem().string(),
                     "ti_iwr6843_rio",
                     "mems",
                     readTrajectory(f, TrajectoryFormat::Tum),
                     false,
                     10,
                     {10, 50}});
  if (!boreas.empty()) {
    const Trajectory car = firstSeconds(boreasRadarTrajectory6Dof(readBoreasPoses(boreas)), seconds);
    const std::string name = fs::path(boreas).parent_path().parent_path().filename().string();
    for (const std::string imu : {"mems", "navigation"}) {
      cases.push_back({name, "ars548", imu, car, true, 20, {100, 200}});
      cases.push_back({name, "oculii_eagle", imu, car, true, 10, {100, 200}});
    }
  }
  return cases;
}

/// The real TI bag's scans per range band beside the TI preset's along each hand-held case; 1 on error.
int printBandTable(const std::string& rio_bag, const std::vector<Case>& cases, std::uint64_t seed) {
  try {
    std::printf(
        "\nPer range band (5th / 50th / 95th percentiles; |Doppler residual| against the scan's own 3D "
        "ego-velocity):\n\n| scans | range (m) | detections a scan | elevation (deg) | power | |Doppler residual| "
        "(m/s) |\n|---|---|---|---|---|---|\n%s",
        bandRows("the real rio bag", rioScans(rio_bag)).c_str());
    for (const Case& c : cases)
      if (c.preset == "ti_iwr6843_rio") std::printf("%s", tiBandRows(c, seed).c_str());
  } catch (const std::exception& e) {
    std::cerr << "radar_6dof_table: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> handheld;
  std::string boreas;
  double boreas_seconds = 120;
  std::uint64_t seed = 1;
  std::string write_dir, rio_bag;
  po::options_description desc(
      "radar_6dof_table: doppler-imu on the 4D simulator driven by real 6-DoF motion, scored with the 6-DoF "
      "metrics.\nUsage: radar_6dof_table --handheld FILE... [--boreas POSES.csv]\nOptions");
  desc.add_options()("help,h", "this help")(
      "handheld", po::value(&handheld)->multitoken(),
      "hand-held TUM trajectories (e.g. ../shared/data/handheld-6dof/carried_1.txt): the TI preset, a MEMS IMU")(
      "boreas", po::value(&boreas),
      "a Boreas applanix/radar_poses.csv: the ARS548 and Oculii presets, MEMS and navigation IMUs")(
      "boreas-seconds", po::value(&boreas_seconds)->default_value(120), "the Boreas drive's first seconds (0: all)")(
      "seed", po::value(&seed)->default_value(1), "the simulation's seed")(
      "write", po::value(&write_dir), "a folder for each case's truth and estimate (TUM) for radar_eval")(
      "rio-bag", po::value(&rio_bag),
      "the real TI bag (../shared/data/ros-rio-ti-mmwave/ti_mmwave_rospkg_demo.bag): its scans per range band beside "
      "the TI preset's along each hand-held trajectory, at the rig's mounting");
  po::variables_map vm;
  try {
    po::store(po::parse_command_line(argc, argv, desc), vm);
    po::notify(vm);
  } catch (const std::exception& e) {
    std::cerr << "radar_6dof_table: " << e.what() << "\n" << desc;
    return 2;
  }
  if (vm.count("help") || (handheld.empty() && boreas.empty())) {
    std::cout << desc;
    return vm.count("help") ? 0 : 2;
  }
  std::vector<Case> cases;
  try {
    cases = buildCases(handheld, boreas, boreas_seconds);
    if (!write_dir.empty()) fs::create_directories(write_dir);
  } catch (const std::exception& e) {
    std::cerr << "radar_6dof_table: " << e.what() << "\n";
    return 1;
  }
  std::printf(
      "| driver | preset | IMU | length (m) | scans | valid ego-velocities | ego-velocity median error (m/s) | "
      "ATE posyaw (m) | "
      "rot. RMSE (deg) | RE short: %% / yaw deg | RE long: %% / yaw deg | final (%%) | s |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Case& c : cases) {
    try {
      runCase(c, seed, write_dir);
    } catch (const std::exception& e) {
      std::cerr << "radar_6dof_table: " << c.driver << " " << c.preset << ": " << e.what() << "\n";
      return 1;
    }
  }
  std::printf(
      "\nThe simulated scans (5th / 50th / 95th percentiles):\n\n| driver | preset | detections a scan | range (m) | "
      "azimuth (deg) | elevation (deg) | Doppler (m/s) |\n|---|---|---|---|---|---|---|\n");
  for (const auto& row : statistics_rows) std::printf("%s\n", row.c_str());
  return rio_bag.empty() ? 0 : printBandTable(rio_bag, cases, seed);
}

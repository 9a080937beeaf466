// radar_6dof_table: the 6-DoF accuracy table on the 4D simulator driven by real motion. Each real
// trajectory (hand-held TUM files with the TI preset, a Boreas pose file with the car presets)
// becomes a smooth motion (radar_ndt/sim/motion_6dof.h); a world is built around its path; the
// radar's scans and a 6-axis IMU are simulated along it; each method runs on them and is scored
// against the motion with the 6-DoF metrics (rpg's ATE after position + yaw alignment, its
// relative error, the final position error). The rows (--methods): the doppler-imu baseline, the
// IMU alone, and the 6-DoF odometry (odometry/radar_inertial_odometry.h) with each 3D matcher of
// the registry, radar only and with the IMU fused.
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
#include "radar_ndt/odometry/radar_inertial_odometry.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/se3.h"
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

/// One method's trajectory on a sequence, with its fallbacks and its time per scan.
struct MethodRun {
  Trajectory trajectory;
  std::size_t fallbacks = 0;
  double ms_per_scan = 0;
  std::vector<std::string> problems;
};

double msPerScan(std::chrono::steady_clock::time_point t0, std::size_t scans) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() /
         static_cast<double>(std::max<std::size_t>(1, scans));
}

/// doppler-imu: each scan's 3D Doppler velocity (the radar at the body's origin), the IMU.
MethodRun runBaseline(const sim::Radar4DSequence& seq) {
  const auto t0 = std::chrono::steady_clock::now();
  const EgoVelocity3DEstimator estimator;
  std::vector<BodyVelocitySample> velocities;
  for (std::size_t k = 0; k < seq.scans.size(); ++k) {
    const EgoVelocity3D e = estimator.estimate(seq.scans[k]);
    velocities.push_back({seq.stamps[k], e.velocity, e.valid});
  }
  const DopplerImuResult r = runDopplerImu(seq.imu, velocities);
  MethodRun out{r.trajectory, 0, 0, r.problems};
  out.ms_per_scan = msPerScan(t0, seq.scans.size());
  return out;
}

/// The IMU alone: strapdown from the still start (roll, pitch, the gyro's bias), the
/// accelerometer less gravity integrated twice; no radar.
MethodRun runImuAlone(const sim::Radar4DSequence& seq) {
  const auto t0 = std::chrono::steady_clock::now();
  MethodRun out;
  const InertialFilterOptions o;
  const StillStart start = readStillStart(seq.imu, o.initial_seconds, o.gravity, out.problems);
  Eigen::Matrix3d R = start.attitude;
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), p = Eigen::Vector3d::Zero();
  std::size_t k = 0;
  for (std::size_t i = 1; i < seq.imu.size() && k < seq.stamps.size(); ++i) {
    const ImuSample &a = seq.imu[i - 1], &b = seq.imu[i];
    const double dt = b.t - a.t;
    const Eigen::Matrix3d R0 = R;
    R = R * expSO3((0.5 * (a.gyro + b.gyro) - start.gyro_bias) * dt);
    const Eigen::Vector3d acc = 0.5 * (R0 * a.accel + R * b.accel) - o.gravity * Eigen::Vector3d::UnitZ();
    p += v * dt + 0.5 * acc * dt * dt;
    v += acc * dt;
    for (; k < seq.stamps.size() && seq.stamps[k] <= b.t; ++k) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = R;
      T.translation() = p;
      out.trajectory.stamps.push_back(seq.stamps[k]);
      out.trajectory.poses.push_back(T);
    }
  }
  out.ms_per_scan = msPerScan(t0, seq.scans.size());
  return out;
}

/// The 6-DoF odometry with `matcher`, the IMU fused or not, each IMU message handed over before
/// the scans after it, as a live run would.
MethodRun runOdometry(const sim::Radar4DSequence& seq, const std::string& matcher, bool imu) {
  RadarInertialOptions o;
  o.method = matcher;
  o.use_imu = imu;
  RadarInertialOdometry odometry(o);
  MethodRun out;
  std::size_t next_imu = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < seq.scans.size(); ++k) {
    for (; next_imu < seq.imu.size() && seq.imu[next_imu].t <= seq.stamps[k]; ++next_imu)
      odometry.addImu(seq.imu[next_imu]);
    const OdometryStep3D step = odometry.addScan(seq.stamps[k], seq.scans[k]);
    if (step.skipped) continue;
    out.trajectory.stamps.push_back(step.stamp);
    out.trajectory.poses.push_back(step.pose);
    out.fallbacks += step.fallback;
  }
  out.ms_per_scan = msPerScan(t0, seq.scans.size());
  out.problems = odometry.problems();
  return out;
}

/// The matcher's own error: each scan's static detections matched from its true pose against a
/// local map placed at the true poses (the poses taken relative to the first, so that the map's
/// coordinates stay small). Prints the error's percentiles and its mean in the body's axes
/// (a bias) to stderr.
void truthMatch(const sim::Radar4DSequence& seq, const std::string& matcher) {
  const auto reg = findMatcher3D(matcher).make(Matcher3DOptions{});
  LocalMap3D map;
  const EgoVelocity3DEstimator estimator;
  std::vector<double> translation, rotation, yaw;
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < seq.scans.size(); ++k) {
    std::vector<bool> inlier;
    const EgoVelocity3D e = estimator.estimate(seq.scans[k], &inlier);
    pcl::PointCloud<PointRadar4D>::Ptr source(new pcl::PointCloud<PointRadar4D>);
    for (std::size_t i = 0; i < inlier.size(); ++i)
      if (!e.valid || inlier[i]) source->push_back(seq.scans[k][i]);
    const Eigen::Isometry3d T = seq.truth.poses[0].inverse() * seq.truth.poses[k];
    if (!map.empty() && source->size() >= 6) {
      reg->setInputTarget(map.cloud());
      reg->setInputSource(source);
      pcl::PointCloud<PointRadar4D> aligned;
      reg->align(aligned, T.matrix().cast<float>());
      const Eigen::Isometry3d M = toPose3(reg->getFinalTransformation());
      translation.push_back((M.translation() - T.translation()).norm());
      rotation.push_back(Eigen::AngleAxisd((T.inverse() * M).linear()).angle() * 180 / kPi);
      yaw.push_back(logSO3(M.linear() * T.linear().transpose()).z() * 180 / kPi);
      bias += T.linear().transpose() * (M.translation() - T.translation());
    }
    if (map.wantsKeyframe(T)) map.add(*source, T);
  }
  bias /= static_cast<double>(std::max<std::size_t>(1, translation.size()));
  std::fprintf(stderr,
               "%s from the truth: translation %s m, rotation %s deg, world yaw %s deg (5th / 50th / 95th); "
               "mean translation error in the body's axes %.3f %.3f %.3f m\n",
               matcher.c_str(), percentiles(translation, "%.3f").c_str(), percentiles(rotation, "%.2f").c_str(),
               percentiles(yaw, "%.2f").c_str(), bias.x(), bias.y(), bias.z());
}

MethodRun runMethod(const sim::Radar4DSequence& seq, const std::string& method) {
  if (method == "doppler-imu") return runBaseline(seq);
  if (method == "imu") return runImuAlone(seq);
  const std::string fused = "+imu";
  const bool imu =
      method.size() > fused.size() && method.compare(method.size() - fused.size(), fused.size(), fused) == 0;
  return runOdometry(seq, imu ? method.substr(0, method.size() - fused.size()) : method, imu);
}

/// The median error of the scans' 3D Doppler velocity against the motion's, and the valid scans.
std::pair<double, std::size_t> velocityError(const sim::Motion6Dof& motion, const sim::Radar4DSequence& seq) {
  const EgoVelocity3DEstimator estimator;
  std::vector<double> errors;
  for (std::size_t k = 0; k < seq.scans.size(); ++k) {
    const EgoVelocity3D e = estimator.estimate(seq.scans[k]);
    if (e.valid)
      errors.push_back((e.velocity - seq.truth.poses[k].linear().transpose() * motion.velocity(seq.stamps[k])).norm());
  }
  std::sort(errors.begin(), errors.end());
  return {errors.empty() ? NAN : errors[errors.size() / 2], errors.size()};
}

/// `seq`'s scans as the preset's sensor description reads its driver's recordings: where the
/// description maps no field to the power (the TI driver's intensity, an SNR, is not read as a
/// weight; Snail-Radar's ARS548 gives only its RCS), every detection weighs the same, as it does
/// when a recording is read (radar_point_fields.h).
void readAsDescribed(const std::string& preset, sim::Radar4DSequence& seq) {
  const SensorDescription d = readSensorDescription("preset:" + sim::radar4DSensorPreset(preset));
  if (!d.radars.front().fields.power.empty()) return;
  for (auto& scan : seq.scans)
    for (PointRadar4D& p : scan) p.power = 1.f;
}

void runCase(const Case& c, const std::vector<std::string>& methods, std::uint64_t seed, const std::string& write_dir) {
  const sim::Motion6Dof motion(c.trajectory);
  const sim::World3D world = sim::worldAlongPath(motion, c.car, seed);
  sim::Radar4DSequence seq =
      sim::simulateRadar4DSequence(motion, world, sim::radar4DPreset(c.preset), c.rate, sim::imu6Preset(c.imu), seed);
  readAsDescribed(c.preset, seq);
  if (c.imu == "mems") statistics_rows.push_back(scanStatistics(c, seq));
  const auto [velocity_error, valid] = velocityError(motion, seq);
  if (!write_dir.empty()) writeTum(write_dir + "/" + c.driver + "_" + c.preset + "_" + c.imu + "_truth.tum", seq.truth);
  for (const std::string& method : methods) {
    if (method.rfind("truth:", 0) == 0) {
      truthMatch(seq, method.substr(6));
      continue;
    }
    const MethodRun r = runMethod(seq, method);
    const PosePairs pairs = associate(seq.truth, r.trajectory);
    const AbsoluteError6Dof ate = absoluteTrajectoryError6Dof(pairs, TrajectoryAlignment::PositionYaw);
    const AbsoluteError6Dof ate_se3 = absoluteTrajectoryError6Dof(pairs, TrajectoryAlignment::SE3);
    const FinalError final_error = finalPositionError(pairs);
    std::string re;
    for (double d : c.distances) {
      const RelativeError e = relativeError(pairs, d);
      re += " " + fmt(e.trans_mean_pct) + " / " + fmt(e.yaw_mean_deg) + " |";
    }
    std::printf("| %s | %s | %s | %s | %.0f | %zu | %zu | %s | %zu | %s | %s | %s |%s %s | %.2f |\n", c.driver.c_str(),
                c.preset.c_str(), c.imu.c_str(), method.c_str(), motion.length(), seq.scans.size(), valid,
                fmt(velocity_error, "%.3f").c_str(), r.fallbacks, fmt(ate.rmse_m).c_str(), fmt(ate_se3.rmse_m).c_str(),
                fmt(ate.rot_rmse_deg).c_str(), re.c_str(), fmt(final_error.final_pct).c_str(), r.ms_per_scan);
    std::fflush(stdout);
    for (const auto& p : r.problems)
      std::fprintf(stderr, "%s %s %s: %s\n", c.driver.c_str(), c.preset.c_str(), method.c_str(), p.c_str());
    if (!write_dir.empty())
      writeTum(write_dir + "/" + c.driver + "_" + c.preset + "_" + c.imu + "_" + method + ".tum", r.trajectory);
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

/// "a,b,,c" as {"a", "b", "c"}.
std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  for (std::size_t a = 0; a <= text.size();) {
    const std::size_t b = std::min(text.find(',', a), text.size());
    if (b > a) out.push_back(text.substr(a, b - a));
    a = b + 1;
  }
  return out;
}

/// The accuracy table: a row per case and method; 1 on error.
int runCases(const std::vector<Case>& cases, const std::vector<std::string>& methods, std::uint64_t seed,
             const std::string& write_dir) {
  std::printf(
      "| driver | preset | IMU | method | length (m) | scans | valid ego-velocities | ego-velocity median error (m/s) "
      "| fallbacks | ATE posyaw (m) | ATE SE(3) (m) | rot. RMSE (deg) | RE short: %% / yaw deg | RE long: %% / yaw "
      "deg | final (%%) | ms a scan |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Case& c : cases) {
    try {
      runCase(c, methods, seed, write_dir);
    } catch (const std::exception& e) {
      std::cerr << "radar_6dof_table: " << c.driver << " " << c.preset << ": " << e.what() << "\n";
      return 1;
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> handheld;
  std::string boreas;
  double boreas_seconds = 120;
  std::uint64_t seed = 1;
  std::string write_dir, rio_bag, methods_text = "doppler-imu";
  po::options_description desc(
      "radar_6dof_table: the 6-DoF odometry, doppler-imu and the IMU alone on the 4D simulator driven by real 6-DoF "
      "motion, scored with the 6-DoF "
      "metrics.\nUsage: radar_6dof_table --handheld FILE... [--boreas POSES.csv]\nOptions");
  desc.add_options()("help,h", "this help")(
      "handheld", po::value(&handheld)->multitoken(),
      "hand-held TUM trajectories (e.g. ../shared/data/handheld-6dof/carried_1.txt): the TI preset, a MEMS IMU")(
      "boreas", po::value(&boreas),
      "a Boreas applanix/radar_poses.csv: the ARS548 and Oculii presets, MEMS and navigation IMUs")(
      "boreas-seconds", po::value(&boreas_seconds)->default_value(120), "the Boreas drive's first seconds (0: all)")(
      "seed", po::value(&seed)->default_value(1), "the simulation's seed")(
      "methods", po::value(&methods_text)->default_value(methods_text),
      "comma-separated rows: doppler-imu; imu (the IMU alone); a 3D matcher of the registry (pw-ndt-3d, pcl-ndt-3d, "
      "pcl-gicp) in the 6-DoF odometry, radar only, or with +imu the IMU fused (e.g. pw-ndt-3d+imu); truth:MATCHER "
      "prints the matcher's own error from the true poses (stderr)")(
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
  if (runCases(cases, splitList(methods_text), seed, write_dir) != 0) return 1;
  std::printf(
      "\nThe simulated scans (5th / 50th / 95th percentiles):\n\n| driver | preset | detections a scan | range (m) | "
      "azimuth (deg) | elevation (deg) | Doppler (m/s) |\n|---|---|---|---|---|---|---|\n");
  for (const auto& row : statistics_rows) std::printf("%s\n", row.c_str());
  return rio_bag.empty() ? 0 : printBandTable(rio_bag, cases, seed);
}

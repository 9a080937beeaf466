#include "sim/sim_4d.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <pcl/io/pcd_io.h>

#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/boreas_ground_truth.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/sim/motion_6dof.h"
#include "radar_ndt/sim/radar_4d.h"
#ifdef RADAR_NDT_WITH_ROS
#include "radar_ndt/ros/radar_4d_bag.h"
#endif

namespace radar_ndt {
namespace apps {

namespace fs = std::filesystem;

namespace {

/// 2021-01-01: the built-in motions' first time, so every stamp is a date as recorders write.
constexpr double kBuiltinStart = 1609459200.0;

bool isCar(const std::string& preset) {
  return preset != "ti_iwr6843_rio";
}

/// A pose from position and roll, pitch, yaw (R = Rz Ry Rx, as the sensor descriptions).
Eigen::Isometry3d poseOf(const Eigen::Vector3d& p, double roll, double pitch, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = p;
  return T;
}

/// Straight stretches and turns (length m, curvature 1/m, grade), driven at `speed` m/s after a
/// still start, sampled at 10 Hz; `wobble` adds a hand-held rig's sway (roll, pitch, bob at the
/// step frequency).
Trajectory builtinMotion(bool car) {
  struct Segment {
    double length, curvature, grade;
  };
  const double speed = car ? 10.0 : 1.2;
  // The car: a street, a left turn, a ramp up and a right turn (about 60 s); the walk: two laps of
  // a 20 m x 12 m corridor loop (about 110 s).
  const std::vector<Segment> car_route = {{150, 0, 0}, {47.1, 1 / 30.0, 0},  {60, 0, 0.05},
                                          {80, 0, 0},  {47.1, -1 / 30.0, 0}, {200, 0, 0}};
  std::vector<Segment> walk_route;
  for (int lap = 0; lap < 2; ++lap)
    for (double side : {20.0, 12.0, 20.0, 12.0}) {
      walk_route.push_back({side - 2.0, 0, 0});
      walk_route.push_back({kPi / 2, 1.0, 0});  // a quarter turn of 1 m radius
    }
  const std::vector<Segment>& route = car ? car_route : walk_route;
  Trajectory t;
  Eigen::Vector3d p(0, 0, 0);
  double yaw = 0, time = 0;
  const double dt = 0.1, still = 2.0;
  std::size_t s = 0;
  double along = 0;  // m into segment s
  while (s < route.size()) {
    const bool moving = time >= still;
    const double grade = route[s].grade;
    double pitch = -std::atan(grade), roll = 0, bob = 0;
    if (!car) {
      const double step = 2 * kPi * 1.8 * time;
      roll = 0.035 * std::sin(step / 2);
      pitch += 0.05 * std::sin(step / 2 + 0.7);
      bob = 0.03 * std::sin(step);
    }
    t.stamps.push_back(kBuiltinStart + time);
    t.poses.push_back(poseOf(p + Eigen::Vector3d(0, 0, bob), roll, pitch, yaw));
    time += dt;
    if (!moving) continue;
    const double ds = speed * dt;
    yaw += route[s].curvature * ds;
    p += ds * Eigen::Vector3d(std::cos(yaw), std::sin(yaw), grade);
    along += ds;
    if (along >= route[s].length) {
      along = 0;
      ++s;
    }
  }
  return t;
}

Trajectory loadTrajectory(const std::string& path, bool car) {
  if (path.empty()) return builtinMotion(car);
  if (detectTrajectoryFormat(path) == TrajectoryFormat::Boreas) return boreasRadarTrajectory6Dof(readBoreasPoses(path));
  return readTrajectory(path);
}

/// The trajectory cut to what `frames` scans at `rate` need (the spline's first and last knot
/// spans and a second of margin).
Trajectory cutForFrames(Trajectory t, std::size_t frames, double rate) {
  if (frames == 0 || !t.hasStamps()) return t;
  const double end = t.stamps.front() + static_cast<double>(frames) / rate + 2.0;
  while (t.size() > 8 && t.stamps.back() > end) {
    t.stamps.pop_back();
    t.poses.pop_back();
  }
  return t;
}

std::string readText(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path, "cannot open the sensor description");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The description's file: `preset:NAME` is the preset's file.
std::string descriptionFile(const std::string& sensors) {
  const std::string prefix = "preset:";
  if (sensors.rfind(prefix, 0) == 0) return sensorPresetDirectory() + "/" + sensors.substr(prefix.size()) + ".yaml";
  return sensors;
}

void writePcds(const fs::path& dir, const sim::Radar4DSequence& seq) {
  fs::create_directories(dir);
  for (std::size_t k = 0; k < seq.scans.size(); ++k) {
    const long long us = std::llround(seq.stamps[k] * 1e6);
    const std::string path = (dir / (std::to_string(us) + ".pcd")).string();
    if (seq.scans[k].empty()) {
      // PCL refuses to write an empty cloud; an empty scan is a header without points.
      writeFileAtomically(
          path,
          "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z power rcs cov_xx cov_xy cov_xz "
          "cov_yy cov_yz cov_zz doppler time_offset sensor_id\nSIZE 4 4 4 4 4 4 4 4 4 4 4 4 4 2\nTYPE F F F F F "
          "F F F F F F F F U\nCOUNT 1 1 1 1 1 1 1 1 1 1 1 1 1 1\nWIDTH 0\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\n"
          "POINTS 0\nDATA ascii\n");
      continue;
    }
    if (pcl::io::savePCDFileBinary(path, seq.scans[k]) != 0) throw IoError(path, "cannot write the scan");
  }
}

/// DIR/radar.bag in the preset's driver's layout, read with DIR/sensors.yaml; what was written.
std::string writeBag(const Sim4DRequest& r, const sim::Radar4DSequence& seq, const fs::path& out, bool with_imu,
                     const std::string& topic) {
#ifdef RADAR_NDT_WITH_ROS
  ros1::Radar4DRecording rec;
  rec.stamps = seq.stamps;
  rec.scans = seq.scans;
  rec.truth = seq.truth;
  if (with_imu && !seq.stamps.empty())
    for (const ImuSample& s : seq.imu)
      if (s.t >= seq.stamps.front() - 1.0 && s.t <= seq.stamps.back() + 1.0) rec.imu.push_back({s.t, s.gyro, s.accel});
  const ros1::Radar4DBagLayout layout = r.preset == "ti_iwr6843_rio" ? ros1::Radar4DBagLayout::TiMmwave
                                        : r.preset == "ars548"       ? ros1::Radar4DBagLayout::SnailArs548
                                                                     : ros1::Radar4DBagLayout::NtuEagle;
  const SensorDescription with_truth = readSensorDescription((out / "sensors.yaml").string());
  const ros1::Radar4DBagStats stats = ros1::writeRadar4DBag((out / "radar.bag").string(), layout, with_truth, rec);
  return ", radar.bag (" + std::to_string(stats.scans) + " scans on " + topic + ", " + std::to_string(stats.imu) +
         " IMU messages, " + std::to_string(stats.ground_truth) + " /gt)";
#else
  (void)r, (void)seq, (void)out, (void)with_imu, (void)topic;
  return " (no radar.bag: built without ROS)";
#endif
}

}  // namespace

std::string sensorPresetFor(const std::string& radar_preset) {
  try {
    return sim::radar4DSensorPreset(radar_preset);
  } catch (const std::invalid_argument&) {
    throw std::invalid_argument("--preset must be one of ti_iwr6843_rio, ars548, oculii_eagle, not '" + radar_preset +
                                "'");
  }
}

void writeSequence4D(const Sim4DRequest& r) {
  if (r.out.empty()) throw std::invalid_argument("--out is required");
  const std::string sensors = r.sensors.empty() ? "preset:" + sensorPresetFor(r.preset) : r.sensors;
  sensorPresetFor(r.preset);  // the preset's name checked before any work
  const sim::Radar4DModel model = sim::radar4DPreset(r.preset);
  const bool car = isCar(r.preset);
  const double rate = r.rate > 0 ? r.rate : (r.preset == "ars548" ? 20.0 : 10.0);
  const bool with_imu = r.imu != "none";
  const sim::Imu6Options imu = sim::imu6Preset(r.imu);
  const SensorDescription description = readSensorDescription(sensors);
  if (description.radars.empty()) throw IoError(sensors, "the description names no radar");
  const RadarDescription& radar = description.radars.front();
  const Eigen::Isometry3d mounting =
      radar.mounting ? radar.mounting->transform() : Eigen::Isometry3d(Eigen::Isometry3d::Identity());

  const auto t0 = std::chrono::steady_clock::now();
  const Trajectory trajectory = cutForFrames(loadTrajectory(r.trajectory, car), r.frames, rate);
  const sim::Motion6Dof motion(trajectory);
  const sim::World3D world = sim::worldAlongPath(motion, car, r.seed);
  sim::Radar4DSequence seq = sim::simulateRadar4DSequence(motion, world, model, rate, imu, r.seed, mounting);
  if (r.frames > 0 && seq.scans.size() > r.frames) {
    seq.scans.resize(r.frames);
    seq.stamps.resize(r.frames);
    seq.truth.stamps.resize(r.frames);
    seq.truth.poses.resize(r.frames);
  }

  const fs::path out(r.out);
  fs::create_directories(out);
  writeTum((out / "groundtruth.txt").string(), seq.truth);
  writePcds(out / "radar", seq);
  // The description the bag is read with: the preset's (or the given) file, with the ground truth.
  std::string text = readText(descriptionFile(sensors));
  if (description.ground_truth_topic.empty()) text += "\n# radar_sim: the simulation's truth\nground_truth: /gt\n";
  writeFileAtomically((out / "sensors.yaml").string(), text);
  const std::string bag = writeBag(r, seq, out, with_imu, radar.topic);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::size_t points = 0;
  for (const auto& s : seq.scans) points += s.size();
  std::printf(
      "radar_sim: 4d %s, %zu scans at %.0f Hz (%.1f detections a scan) over %.1f s and %.0f m along %s, IMU "
      "%s, seed %llu -> %s: groundtruth.txt, radar/*.pcd, sensors.yaml%s (%.1f s)\n",
      r.preset.c_str(), seq.scans.size(), rate,
      seq.scans.empty() ? 0.0 : static_cast<double>(points) / static_cast<double>(seq.scans.size()),
      seq.stamps.empty() ? 0.0 : seq.stamps.back() - seq.stamps.front(), motion.length(),
      r.trajectory.empty() ? (car ? "the built-in drive" : "the built-in walk") : r.trajectory.c_str(), r.imu.c_str(),
      static_cast<unsigned long long>(r.seed), r.out.c_str(), bag.c_str(), seconds);
}

}  // namespace apps
}  // namespace radar_ndt

#include "radar_ndt/io/boreas_ground_truth.h"

#include <cmath>
#include <sstream>

#include "boreas_poses_text.h"
#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/boreas_scan.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/se2.h"
#include "read_file.h"
#include "text_lines.h"

namespace radar_ndt {
namespace {

const char* const kColumns[] = {"GPSTime", "easting", "northing", "altitude", "vel_east", "vel_north", "vel_up",
                                "roll",    "pitch",   "heading",  "angvel_z", "angvel_y", "angvel_x"};
constexpr std::size_t kColumnCount = sizeof(kColumns) / sizeof(kColumns[0]);

// The SDK's elementary rotations (pyboreas/utils/utils.py roll, pitch, yaw): passive, so
// yaw(h) = [[c, s, 0], [−s, c, 0], [0, 0, 1]].
Eigen::Matrix3d sdkRoll(double r) {
  Eigen::Matrix3d m;
  m << 1, 0, 0, 0, std::cos(r), std::sin(r), 0, -std::sin(r), std::cos(r);
  return m;
}
Eigen::Matrix3d sdkPitch(double p) {
  Eigen::Matrix3d m;
  m << std::cos(p), 0, -std::sin(p), 0, 1, 0, std::sin(p), 0, std::cos(p);
  return m;
}
Eigen::Matrix3d sdkYaw(double y) {
  Eigen::Matrix3d m;
  m << std::cos(y), std::sin(y), 0, -std::sin(y), std::cos(y), 0, 0, 0, 1;
  return m;
}

void checkHeader(const std::string& path, const std::string& line) {
  const std::vector<std::string> cells = detail::splitCsv(line);
  if (cells.size() != kColumnCount)
    throw IoError(path, 1,
                  "header has " + std::to_string(cells.size()) +
                      " columns, expected the 13 of a Boreas pose file "
                      "(GPSTime,easting,northing,altitude,vel_east,vel_north,vel_up,roll,pitch,heading,angvel_z,"
                      "angvel_y,angvel_x)");
  for (std::size_t i = 0; i < kColumnCount; ++i)
    if (cells[i] != kColumns[i])
      throw IoError(
          path, 1, "header column " + std::to_string(i + 1) + " is '" + cells[i] + "', expected '" + kColumns[i] + "'");
}

BoreasPose parseRow(const std::string& path, std::size_t n, const std::string& line) {
  const std::vector<std::string> cells = detail::splitCsv(line);
  if (cells.size() != kColumnCount)
    throw IoError(path, n, "expected 13 columns, found " + std::to_string(cells.size()));
  BoreasPose p;
  if (!boreasTimeSeconds(cells[0], &p.time_s) || !boreasTimeMicros(cells[0], &p.stamp_us))
    throw IoError(path, n, "GPSTime '" + cells[0] + "' is not a time (digits: µs, ns or s)");
  p.time_digits = static_cast<int>(cells[0].size());
  double v[kColumnCount];
  for (std::size_t i = 1; i < kColumnCount; ++i) v[i] = detail::parseFinite(path, n, cells[i], kColumns[i]);
  p.position = {v[1], v[2], v[3]};
  p.velocity = {v[4], v[5], v[6]};
  p.roll = v[7];
  p.pitch = v[8];
  p.heading = v[9];
  p.angular_velocity = {v[12], v[11], v[10]};  // the file's order is z, y, x
  return p;
}

}  // namespace

Eigen::Matrix3d boreasRotation(const BoreasPose& pose, bool planar) {
  // pyboreas/utils/odometry.py convert_line_to_pose, dim == 2: roll and pitch rounded to k·π.
  const double roll = planar ? std::round(pose.roll / kPi) * kPi : pose.roll;
  const double pitch = planar ? std::round(pose.pitch / kPi) * kPi : pose.pitch;
  return sdkRoll(roll) * sdkPitch(pitch) * sdkYaw(pose.heading);
}

Eigen::Isometry3d boreasSensorPose(const BoreasPose& pose, bool planar) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = boreasRotation(pose, planar);
  t.translation() = pose.position;
  if (planar) t.translation().z() = 0.0;
  return t;
}

std::vector<BoreasPose> readBoreasPoses(const std::string& path) {
  return detail::parseBoreasPoses(path, detail::readWholeFile(path));
}

std::vector<BoreasPose> detail::parseBoreasPoses(const std::string& path, const std::string& text) {
  if (text.empty()) throw IoError(path, "empty file, expected a header line");
  std::vector<BoreasPose> out;
  detail::forEachLine(text, [&](std::size_t n, const std::string& line) {
    if (n == 1) {
      checkHeader(path, line);
      return true;
    }
    if (detail::isBlank(line)) return true;
    BoreasPose p = parseRow(path, n, line);
    if (!out.empty() && p.stamp_us <= out.back().stamp_us)
      throw IoError(path, n,
                    "GPSTime " + std::to_string(p.stamp_us) + " µs is not after the previous row's " +
                        std::to_string(out.back().stamp_us));
    out.push_back(p);
    return true;
  });
  if (out.empty()) throw IoError(path, "no pose rows after the header");
  return out;
}

void writeBoreasPoses(const std::string& path, const std::vector<BoreasPose>& rows) {
  std::ostringstream s;
  s.precision(17);
  for (std::size_t i = 0; i < kColumnCount; ++i) s << (i ? "," : "") << kColumns[i];
  s << '\n';
  for (const BoreasPose& p : rows) {
    s << p.stamp_us << "000";  // nanoseconds, as the released files
    for (double v :
         {p.position.x(), p.position.y(), p.position.z(), p.velocity.x(), p.velocity.y(), p.velocity.z(), p.roll,
          p.pitch, p.heading, p.angular_velocity.z(), p.angular_velocity.y(), p.angular_velocity.x()})
      s << ',' << v;
    s << '\n';
  }
  writeFileAtomically(path, s.str());
}

Trajectory boreasRadarTrajectory(const std::vector<BoreasPose>& rows) {
  // The radar's axes (x forward, y right, z down) to the vehicle's (x forward, y left, z up).
  Eigen::Isometry3d flip = Eigen::Isometry3d::Identity();
  flip.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  Trajectory t;
  for (const BoreasPose& p : rows) {
    const Eigen::Isometry3d pose = boreasSensorPose(p, true) * flip;
    const double yaw = std::atan2(pose.linear()(1, 0), pose.linear()(0, 0));
    t.stamps.push_back(1e-6 * static_cast<double>(p.stamp_us));
    t.poses.push_back(toIsometry3(Pose2(pose.translation().x(), pose.translation().y(), yaw)));
  }
  return t;
}

Trajectory boreasRadarTrajectory6Dof(const std::vector<BoreasPose>& rows) {
  Eigen::Isometry3d flip = Eigen::Isometry3d::Identity();
  flip.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  Trajectory t;
  for (const BoreasPose& p : rows) {
    t.stamps.push_back(1e-6 * static_cast<double>(p.stamp_us));
    t.poses.push_back(boreasSensorPose(p, false) * flip);
  }
  return t;
}

BoreasPose boreasPoseFromPlanar(double time_s, double x, double y, double yaw, double vx, double vy, double yaw_rate) {
  BoreasPose p;
  p.stamp_us = static_cast<std::int64_t>(std::llround(time_s * 1e6));
  p.time_s = 1e-6 * static_cast<double>(p.stamp_us);
  p.time_digits = 19;
  p.position = {x, y, 0.0};
  const double c = std::cos(yaw), s = std::sin(yaw);
  p.velocity = {c * vx - s * vy, s * vx + c * vy, 0.0};
  // roll(π) · yaw(h) is Rz(h) · diag(1, −1, −1): the radar's heading is the vehicle's yaw.
  p.roll = kPi;
  p.pitch = 0.0;
  p.heading = yaw;
  p.angular_velocity = {0.0, 0.0, -yaw_rate};  // about the radar's z, which points down
  return p;
}

}  // namespace radar_ndt

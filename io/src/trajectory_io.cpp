#include "radar_ndt/io/trajectory_io.h"

#include <Eigen/SVD>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "boreas_poses_text.h"
#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/boreas_ground_truth.h"
#include "radar_ndt/io/io_error.h"
#include "read_file.h"
#include "rotations.h"
#include "text_lines.h"

namespace radar_ndt {
using detail::nearestRotation;
using detail::orthogonalityError;
using detail::readWholeFile;
namespace {

/// Splits a line into numbers; every token must parse completely as a finite double.
std::vector<double> parseNumbers(const std::string& path, std::size_t line_no, const std::string& line) {
  std::vector<double> values;
  const char* p = line.c_str();
  const char* end = p + line.size();
  while (p < end) {
    while (p < end && (std::isspace(static_cast<unsigned char>(*p)) || *p == ',')) ++p;
    if (p >= end) break;
    const char* token_end = p;
    while (token_end < end && !std::isspace(static_cast<unsigned char>(*token_end)) && *token_end != ',') ++token_end;
    const std::string token(p, token_end);
    char* parsed_end = nullptr;
    errno = 0;
    const double v = std::strtod(token.c_str(), &parsed_end);
    if (parsed_end != token.c_str() + token.size() || token.empty())
      throw IoError(path, line_no, "cannot parse '" + token + "' as a number");
    if (!std::isfinite(v) || errno == ERANGE)
      throw IoError(path, line_no, "non-finite or out-of-range value '" + token + "'");
    values.push_back(v);
    p = token_end;
  }
  return values;
}

/// Calls fn(line_no, numbers) for each line that is neither blank nor a '#' comment; fn returns
/// false to stop.
template <typename Fn>
void forEachDataLine(const std::string& path, const std::string& text, Fn&& fn) {
  detail::forEachLine(text, [&](std::size_t line_no, const std::string& line) {
    const auto first = std::find_if_not(line.begin(), line.end(), [](unsigned char c) { return std::isspace(c); });
    if (first == line.end() || *first == '#') return true;
    if (line.find('\0') != std::string::npos) throw IoError(path, line_no, "binary data in a text file");
    return fn(line_no, parseNumbers(path, line_no, line));
  });
}

// Rotation blocks written with few decimals (CFEAR's KITTI files keep 3) are not orthonormal; such
// files are what users have, so a block near a rotation is projected onto one and counted, and
// only one that is no rotation at all is refused. Beyond this deviation no rounding explains it.
constexpr double kProjectableDeviation = 0.05;

/// Throws when `R` is too far from a rotation to be one rounded; else true when it needs projecting.
bool needsProjection(const std::string& path, std::size_t line_no, const Eigen::Matrix3d& R) {
  const double orth = orthogonalityError(R);
  const double det = R.determinant();
  if (orth > kProjectableDeviation || !(det > 0.0)) {
    std::ostringstream msg;
    msg << "rotation block is not a rotation (|RtR - I| = " << orth << ", det = " << det
        << "; rounding alone gives at most " << kProjectableDeviation << " and det > 0)";
    throw IoError(path, line_no, msg.str());
  }
  // Files written with 9 or more significant digits (this library's writers) are rotations to their
  // precision and are left as read. Below that even 6 decimals matter: near the identity the angle
  // acos((tr R - 1) / 2) turns a 1e-6 deviation into an error of about 1e-3 rad.
  return orth > 1e-8;
}

void noteProjection(Trajectory* t, const Eigen::Matrix3d& R) {
  ++t->projected_rotations;
  t->max_rotation_deviation = std::max(t->max_rotation_deviation, orthogonalityError(R));
}

/// pyboreas utils.enforce_orthog (dim 3), step for step, so that a Boreas file scores exactly as the
/// SDK scores it: columns 1 and 2 normalised, column 0 = c1 x c2, column 1 = c2 x column 0. Left as is
/// when |det - 1| < 1e-10, as there.
Eigen::Matrix3d boreasSdkOrthogonalise(const Eigen::Matrix3d& R) {
  if (std::abs(R.determinant() - 1.0) < 1e-10) return R;
  const Eigen::Vector3d c1 = R.col(1).normalized();
  const Eigen::Vector3d c2 = R.col(2).normalized();
  Eigen::Matrix3d out;
  out.col(0) = c1.cross(c2);
  out.col(1) = c2.cross(Eigen::Vector3d(out.col(0)));
  out.col(2) = c2;
  return out;
}

std::size_t firstDataColumnCount(const std::string& path, const std::string& text) {
  std::size_t count = 0;
  bool found = false;
  forEachDataLine(path, text, [&](std::size_t, const std::vector<double>& v) {
    count = v.size();
    found = true;
    return false;
  });
  if (!found) throw IoError(path, "no poses in the file");
  return count;
}

Trajectory parseKitti(const std::string& path, const std::string& text) {
  Trajectory t;
  forEachDataLine(path, text, [&](std::size_t line_no, const std::vector<double>& v) {
    if (v.size() != 12) throw IoError(path, line_no, "KITTI pose needs 12 numbers, found " + std::to_string(v.size()));
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) T.matrix()(r, c) = v[static_cast<std::size_t>(r * 4 + c)];
    if (needsProjection(path, line_no, T.linear())) {
      noteProjection(&t, T.linear());
      T.linear() = nearestRotation(T.linear());
    }
    t.poses.push_back(T);
    return true;
  });
  if (t.empty()) throw IoError(path, "no poses in the file");
  return t;
}

Trajectory parseTum(const std::string& path, const std::string& text) {
  Trajectory t;
  forEachDataLine(path, text, [&](std::size_t line_no, const std::vector<double>& v) {
    if (v.size() != 8)
      throw IoError(path, line_no, "TUM pose needs 8 numbers (t x y z qx qy qz qw), found " + std::to_string(v.size()));
    if (!t.stamps.empty() && !(v[0] > t.stamps.back())) {
      std::ostringstream msg;
      msg.precision(17);
      msg << "timestamp " << v[0] << " is not after the previous one (" << t.stamps.back() << ")";
      throw IoError(path, line_no, msg.str());
    }
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    const double n = q.norm();
    if (!(std::abs(n - 1.0) < 1e-2)) throw IoError(path, line_no, "quaternion norm " + std::to_string(n) + " is not 1");
    q.normalize();
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.toRotationMatrix();
    T.translation() << v[1], v[2], v[3];
    t.stamps.push_back(v[0]);
    t.poses.push_back(T);
    return true;
  });
  if (t.empty()) throw IoError(path, "no poses in the file");
  return t;
}

// The Boreas leaderboard's radar frame is x forward, y right, z down: F = diag(1, −1, −1) turns
// a pose between vehicle frames into one between radar frames and back (F is its own inverse).
Eigen::Isometry3d flipAxes(const Eigen::Isometry3d& T) {
  Eigen::Isometry3d f = Eigen::Isometry3d::Identity();
  f.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  return f * T * f;
}

// pyboreas/eval/odometry.md: `<timestamp µs> <3x4 of T_rk_r0, row-major>` a line.
Trajectory parseBoreasOdometry(const std::string& path, const std::string& text) {
  Trajectory t;
  forEachDataLine(path, text, [&](std::size_t line_no, const std::vector<double>& v) {
    if (v.size() != 13)
      throw IoError(
          path, line_no,
          "Boreas odometry line needs 13 numbers (µs timestamp, 3x4 pose), found " + std::to_string(v.size()));
    const double stamp = 1e-6 * v[0];
    if (!t.stamps.empty() && !(stamp > t.stamps.back()))
      throw IoError(path, line_no,
                    "timestamp " + std::to_string(static_cast<long long>(v[0])) + " is not after the previous one");
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) T.matrix()(r, c) = v[static_cast<std::size_t>(1 + r * 4 + c)];
    if (needsProjection(path, line_no, T.linear())) noteProjection(&t, T.linear());
    T.linear() = boreasSdkOrthogonalise(T.linear());
    t.stamps.push_back(stamp);
    t.poses.push_back(flipAxes(T.inverse()));
    return true;
  });
  if (t.empty()) throw IoError(path, "no poses in the file");
  return t;
}

bool isBoreasPoseCsv(const std::string& text) {
  return text.compare(0, 8, "GPSTime,") == 0;
}

}  // namespace

Eigen::Isometry3d interpolate(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double u) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const Eigen::Quaterniond qa(a.linear()), qb(b.linear());
  T.linear() = qa.slerp(u, qb).toRotationMatrix();
  T.translation() = (1.0 - u) * a.translation() + u * b.translation();
  return T;
}

bool Trajectory::poseAt(double t, Eigen::Isometry3d* pose) const {
  if (stamps.empty() || stamps.size() != poses.size()) return false;
  if (t < stamps.front() - 1e-6 || t > stamps.back() + 1e-6) return false;
  // k: the last stamp at or before t (0 before the first).
  const auto after = std::upper_bound(stamps.begin(), stamps.end(), t);
  const std::size_t k = after == stamps.begin() ? 0 : static_cast<std::size_t>(after - stamps.begin()) - 1;
  if (k + 1 < stamps.size() && t > stamps[k])
    *pose = interpolate(poses[k], poses[k + 1], (t - stamps[k]) / (stamps[k + 1] - stamps[k]));
  else
    *pose = poses[k];
  return true;
}

TrajectoryFormat parseTrajectoryFormat(const std::string& name) {
  std::string n = name;
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return parseEnum<TrajectoryFormat>(n);
}

Trajectory readKitti(const std::string& path) {
  return parseKitti(path, readWholeFile(path));
}

Trajectory readTum(const std::string& path) {
  return parseTum(path, readWholeFile(path));
}

namespace {

/// The format of `text` by its content: a Boreas pose CSV counts as Boreas.
TrajectoryFormat detectFormat(const std::string& path, const std::string& text) {
  if (isBoreasPoseCsv(text)) return TrajectoryFormat::Boreas;
  const std::size_t columns = firstDataColumnCount(path, text);
  if (columns == 12) return TrajectoryFormat::Kitti;
  if (columns == 8) return TrajectoryFormat::Tum;
  if (columns == 13) return TrajectoryFormat::Boreas;
  throw IoError(path, "cannot tell the trajectory format: the first pose line has " + std::to_string(columns) +
                          " numbers (KITTI has 12, TUM 8, Boreas odometry 13)");
}

}  // namespace

TrajectoryFormat detectTrajectoryFormat(const std::string& path) {
  return detectFormat(path, readWholeFile(path));
}

Trajectory readTrajectory(const std::string& path, TrajectoryFormat format) {
  const std::string text = readWholeFile(path);
  if (format == TrajectoryFormat::Auto && isBoreasPoseCsv(text))
    return boreasRadarTrajectory(detail::parseBoreasPoses(path, text));
  if (format == TrajectoryFormat::Auto) format = detectFormat(path, text);
  if (format == TrajectoryFormat::Boreas) return parseBoreasOdometry(path, text);
  return format == TrajectoryFormat::Kitti ? parseKitti(path, text) : parseTum(path, text);
}

void writeKitti(const std::string& path, const Trajectory& trajectory) {
  std::ostringstream out;
  char buf[64];
  for (const auto& T : trajectory.poses) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) {
        std::snprintf(buf, sizeof(buf), "%.9g", T.matrix()(r, c));
        out << buf << ((r == 2 && c == 3) ? '\n' : ' ');
      }
  }
  writeFileAtomically(path, out.str());
}

void writeTum(const std::string& path, const Trajectory& trajectory) {
  if (trajectory.stamps.size() != trajectory.poses.size())
    throw IoError(path, "TUM output needs one timestamp per pose (" + std::to_string(trajectory.stamps.size()) +
                            " stamps, " + std::to_string(trajectory.poses.size()) + " poses)");
  std::ostringstream out;
  char buf[256];
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const auto& T = trajectory.poses[i];
    const Eigen::Quaterniond q(T.linear());
    std::snprintf(buf, sizeof(buf), "%.6f %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", trajectory.stamps[i],
                  T.translation().x(), T.translation().y(), T.translation().z(), q.x(), q.y(), q.z(), q.w());
    out << buf;
  }
  writeFileAtomically(path, out.str());
}

void writeBoreasOdometry(const std::string& path, const Trajectory& trajectory) {
  if (trajectory.stamps.size() != trajectory.poses.size())
    throw IoError(path, "Boreas odometry output needs one timestamp per pose (" +
                            std::to_string(trajectory.stamps.size()) + " stamps, " +
                            std::to_string(trajectory.poses.size()) + " poses)");
  std::ostringstream out;
  char buf[64];
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const Eigen::Isometry3d T = flipAxes(trajectory.poses[i].inverse());  // T_rk_r0
    out << std::llround(trajectory.stamps[i] * 1e6);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) {
        std::snprintf(buf, sizeof(buf), " %.12g", T.matrix()(r, c) == 0.0 ? 0.0 : T.matrix()(r, c));
        out << buf;
      }
    out << '\n';
  }
  writeFileAtomically(path, out.str());
}

void writeTrajectory(const std::string& path, const Trajectory& trajectory, TrajectoryFormat format) {
  if (format == TrajectoryFormat::Boreas) return writeBoreasOdometry(path, trajectory);
  if (format == TrajectoryFormat::Tum || (format == TrajectoryFormat::Auto && trajectory.hasStamps()))
    writeTum(path, trajectory);
  else
    writeKitti(path, trajectory);
}

}  // namespace radar_ndt

#include "radar_ndt/io/view_of_delft.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include <nlohmann/json.hpp>

#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/io_error.h"
#include "rotations.h"

namespace radar_ndt {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kVodColumns = 7;  // x y z RCS v_r v_r_compensated time

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, "cannot be opened");
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// A row-major 3x4 or 4x4 as a rigid transform; false when the rotation is not one (within what
/// single-precision files round to) or a number is not finite.
bool toRigid(const std::vector<double>& v, Eigen::Isometry3d* T) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) R(r, c) = v[r * 4 + c];
    t(r) = v[r * 4 + 3];
  }
  if (detail::orthogonalityError(R) > 1e-3 || R.determinant() <= 0) return false;
  // Re-orthogonalised: the files hold rounded rotations.
  *T = Eigen::Isometry3d::Identity();
  T->linear() = detail::nearestRotation(R);
  T->translation() = t;
  return true;
}

}  // namespace

pcl::PointCloud<PointRadar4D> readVodRadarBin(const std::string& path, std::vector<float>* compensated,
                                              std::size_t* dropped) {
  const std::string bytes = readAll(path);
  const std::size_t row = kVodColumns * sizeof(float);
  if (bytes.size() % row != 0)
    throw IoError(path, std::to_string(bytes.size()) +
                            " bytes: not a whole number of rows of 7 float32 (x y z RCS v_r "
                            "v_r_compensated time); truncated?");
  pcl::PointCloud<PointRadar4D> cloud;
  if (compensated) compensated->clear();
  std::size_t bad = 0;
  for (std::size_t i = 0; i < bytes.size() / row; ++i) {
    float v[kVodColumns];
    std::memcpy(v, bytes.data() + i * row, row);  // little-endian, as numpy.fromfile writes on x86
    if (!std::all_of(v, v + kVodColumns, [](float x) { return std::isfinite(x); })) {
      ++bad;
      continue;
    }
    PointRadar4D p;
    p.x = v[0];
    p.y = v[1];
    p.z = v[2];
    p.rcs = v[3];
    p.doppler = v[4];
    p.time_offset = static_cast<float>(v[6] * kVodRadarPeriod);
    cloud.push_back(p);
    if (compensated) compensated->push_back(v[5]);
  }
  if (dropped) *dropped = bad;
  return cloud;
}

void writeVodRadarBin(const std::string& path, const pcl::PointCloud<PointRadar4D>& cloud,
                      const std::vector<float>* compensated) {
  if (compensated && compensated->size() != cloud.size())
    throw IoError(path, "v_r_compensated has " + std::to_string(compensated->size()) + " values for " +
                            std::to_string(cloud.size()) + " points");
  std::string bytes(cloud.size() * kVodColumns * sizeof(float), '\0');
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const PointRadar4D& p = cloud[i];
    const float v[kVodColumns] = {p.x,
                                  p.y,
                                  p.z,
                                  p.rcs,
                                  p.doppler,
                                  compensated ? (*compensated)[i] : p.doppler,
                                  static_cast<float>(std::round(p.time_offset / kVodRadarPeriod))};
    std::memcpy(&bytes[i * sizeof v], v, sizeof v);
  }
  writeFileAtomically(path, bytes);
}

Eigen::Isometry3d readVodCameraPose(const std::string& path, const std::string& key) {
  std::istringstream lines(readAll(path));
  std::string line;
  std::size_t number = 0;
  while (std::getline(lines, line)) {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(line);
    } catch (const nlohmann::json::exception& e) {
      throw IoError(path, number, std::string("not JSON: ") + e.what());
    }
    if (!j.is_object() || !j.contains(key)) continue;
    const nlohmann::json& m = j.at(key);
    std::vector<double> v;
    if (m.is_array())
      for (const auto& x : m)
        if (x.is_number()) v.push_back(x.get<double>());
    Eigen::Isometry3d T;
    if (v.size() != 16 || !toRigid(v, &T))
      throw IoError(path, number, "\"" + key + "\" is not 16 finite numbers of a rigid 4x4 transform");
    return T;
  }
  throw IoError(path, "no \"" + key + "\" (a VoD pose file has odomToCamera, mapToCamera and UTMToCamera lines)");
}

Eigen::Isometry3d readVodRadarToCamera(const std::string& path) {
  std::istringstream lines(readAll(path));
  std::string line;
  std::size_t number = 0;
  while (std::getline(lines, line)) {
    ++number;
    if (line.rfind("Tr_velo_to_cam:", 0) != 0) continue;
    std::istringstream in(line.substr(15));
    std::vector<double> v;
    double x;
    while (in >> x) v.push_back(x);
    v.insert(v.end(), {0, 0, 0, 1});
    Eigen::Isometry3d T;
    if (v.size() != 16 || !toRigid(v, &T))
      throw IoError(path, number, "Tr_velo_to_cam is not 12 finite numbers of a rigid 3x4 transform");
    return T;
  }
  throw IoError(path, "no Tr_velo_to_cam line (the radar-to-camera calibration)");
}

ViewOfDelftSequence::ViewOfDelftSequence(const std::string& root, const std::string& split)
    : dir_((fs::path(root) / "radar" / split).string()) {
  const fs::path velodyne = fs::path(dir_) / "velodyne";
  if (!fs::is_directory(velodyne))
    throw IoError(velodyne.string(), "no such folder (View-of-Delft: <root>/radar/<split>/velodyne/NNNNN.bin)");
  for (const auto& e : fs::directory_iterator(velodyne))
    if (e.path().extension() == ".bin") ids_.push_back(e.path().stem().string());
  if (ids_.empty()) throw IoError(velodyne.string(), "holds no .bin radar frame");
  std::sort(ids_.begin(), ids_.end());
}

std::string ViewOfDelftSequence::binPath(std::size_t k) const {
  return (fs::path(dir_) / "velodyne" / (id(k) + ".bin")).string();
}
std::string ViewOfDelftSequence::posePath(std::size_t k) const {
  return (fs::path(dir_) / "pose" / (id(k) + ".json")).string();
}
std::string ViewOfDelftSequence::calibPath(std::size_t k) const {
  return (fs::path(dir_) / "calib" / (id(k) + ".txt")).string();
}

pcl::PointCloud<PointRadar4D> ViewOfDelftSequence::load(std::size_t k, std::vector<float>* compensated) const {
  return readVodRadarBin(binPath(k), compensated);
}

Eigen::Isometry3d ViewOfDelftSequence::radarPose(std::size_t k) const {
  return readVodCameraPose(posePath(k)) * readVodRadarToCamera(calibPath(k));
}

Trajectory ViewOfDelftSequence::radarTrajectory() const {
  Trajectory t;
  for (std::size_t k = 0; k < size(); ++k) t.poses.push_back(radarPose(k));
  return t;
}

}  // namespace radar_ndt

#include "radar_ndt/io/nuscenes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "pcd_header.h"
#include "radar_ndt/io/io_error.h"

namespace radar_ndt {

namespace fs = std::filesystem;
using nlohmann::json;

double ars408RmsValue(int state_index) {
  // ARS408 technical documentation, cluster quality: state index → standard deviation (m or m/s).
  static constexpr std::array<double, 31> kTable{
      0.005, 0.006, 0.008, 0.011, 0.014, 0.018, 0.023, 0.029, 0.038, 0.049, 0.063, 0.081, 0.105, 0.135, 0.174, 0.224,
      0.288, 0.371, 0.478, 0.616, 0.794, 1.023, 1.317, 1.697, 2.187, 2.817, 3.630, 4.676, 6.025, 7.762, 10.0};
  if (state_index < 0 || state_index >= static_cast<int>(kTable.size()))
    return std::numeric_limits<double>::quiet_NaN();
  return kTable[static_cast<std::size_t>(state_index)];
}

// ---- radar PCD --------------------------------------------------------------------------------

RadarPointFields nuScenesArs408Fields(const NuScenesRadarFilter& filter) {
  RadarPointFields f;
  f.doppler = DopplerKind::Components;
  f.vx = "vx";
  f.vy = "vy";
  f.rcs = "rcs";
  f.accuracy = AccuracyKind::Ars408Rms;
  f.accuracy_x = "x_rms";
  f.accuracy_y = "y_rms";
  f.max_range = filter.max_range;
  f.keep = {
      {"invalid_state", filter.invalid_states}, {"dyn_prop", filter.dyn_props}, {"ambig_state", filter.ambig_states}};
  if (!filter.doppler_ambig_states.empty()) f.keep_doppler = {{"ambig_state", filter.doppler_ambig_states}};
  return f;
}

pcl::PointCloud<PointRadar> readNuScenesRadarPcd(const std::string& path, const NuScenesRadarFilter& filter,
                                                 std::uint16_t sensor_id, NuScenesPcdStats* stats) {
  const detail::PcdHeader h = detail::readPcdHeader(path);
  const RadarPointFields fields = nuScenesArs408Fields(filter);
  const std::vector<std::string> columns = fields.columns();
  for (const std::string& name : fields.requiredColumns())
    if (h.find(name) < 0) throw IoError(path, "no field '" + name + "': not a nuScenes radar PCD (needs x y vx vy)");
  std::vector<char> present;
  for (const std::string& name : columns) present.push_back(h.find(name) >= 0);
  // Only the columns used, as doubles: [point][column], NaN where the file lacks the field.
  const std::vector<double> table = detail::readPcdColumns(path, h, columns);
  RadarPointStats s;
  pcl::PointCloud<PointRadar> cloud = convertRadarPoints(table, h.points, present, fields, sensor_id, &s);
  if (stats) *stats = {s.points_in_data, s.kept, s.dropped_by_filter, s.dropped_non_finite};
  return cloud;
}

PcdTable readPcdTable(const std::string& path) {
  const detail::PcdHeader h = detail::readPcdHeader(path);
  PcdTable t;
  for (const auto& f : h.fields) {
    t.names.push_back(f.name);
    t.types.push_back(f.type);
    t.sizes.push_back(f.size);
  }
  t.points = h.points;
  t.values = detail::readPcdColumns(path, h, t.names);
  return t;
}

// ---- JSON tables ------------------------------------------------------------------------------

namespace {

class Table {
 public:
  Table(const std::string& dir, const std::string& name) : file_((fs::path(dir) / (name + ".json")).string()) {
    std::ifstream in(file_, std::ios::binary);
    if (!in)
      throw IoError(file_, "missing table " + name +
                               ".json (needed: sensor, calibrated_sensor, sample_data, ego_pose, sample, scene, log)");
    try {
      rows_ = json::parse(in);
    } catch (const json::exception& e) {
      throw IoError(file_, std::string("invalid JSON: ") + e.what());
    }
    if (!rows_.is_array()) throw IoError(file_, "expected a JSON array of rows");
    for (std::size_t i = 0; i < rows_.size(); ++i)
      if (!rows_[i].is_object()) throw IoError(file_, "row " + std::to_string(i) + " is not a JSON object");
  }
  std::size_t size() const { return rows_.size(); }
  const std::string& file() const { return file_; }

  const json& field(std::size_t row, const char* key) const {
    const auto it = rows_[row].find(key);
    if (it == rows_[row].end()) throw IoError(file_, "row " + std::to_string(row) + ": missing key '" + key + "'");
    return *it;
  }
  std::string str(std::size_t row, const char* key) const {
    const json& v = field(row, key);
    if (!v.is_string()) throw IoError(file_, "row " + std::to_string(row) + ": '" + key + "' is not a string");
    return v.get<std::string>();
  }
  std::int64_t integer(std::size_t row, const char* key) const {
    const json& v = field(row, key);
    if (!v.is_number_integer())
      throw IoError(file_, "row " + std::to_string(row) + ": '" + key + "' is not an integer");
    return v.get<std::int64_t>();
  }
  bool boolean(std::size_t row, const char* key, bool fallback) const {
    const auto it = rows_[row].find(key);
    if (it == rows_[row].end()) return fallback;
    if (!it->is_boolean()) throw IoError(file_, "row " + std::to_string(row) + ": '" + key + "' is not true/false");
    return it->get<bool>();
  }
  std::vector<double> numbers(std::size_t row, const char* key, std::size_t count) const {
    const json& v = field(row, key);
    if (!v.is_array() || v.size() != count)
      throw IoError(file_, "row " + std::to_string(row) + ": '" + key + "' is not an array of " +
                               std::to_string(count) + " numbers");
    std::vector<double> out;
    for (const auto& x : v) {
      if (!x.is_number()) throw IoError(file_, "row " + std::to_string(row) + ": '" + key + "' holds a non-number");
      out.push_back(x.get<double>());
      if (!std::isfinite(out.back()))
        throw IoError(file_, "row " + std::to_string(row) + ": '" + key + "' holds a non-finite number");
    }
    return out;
  }
  /// The rotation [w x y z] as the row holds it.
  Eigen::Vector4d rotation(std::size_t row) const {
    const auto q = numbers(row, "rotation", 4);
    return Eigen::Vector4d(q[0], q[1], q[2], q[3]);
  }
  /// translation [x y z] + rotation [w x y z] → isometry (quaternion normalised; near-zero refused).
  Eigen::Isometry3d pose(std::size_t row) const {
    const auto t = numbers(row, "translation", 3);
    const auto q = numbers(row, "rotation", 4);
    Eigen::Quaterniond quat(q[0], q[1], q[2], q[3]);
    const double norm = quat.norm();
    if (!(std::abs(norm - 1.0) < 1e-2))
      throw IoError(file_, "row " + std::to_string(row) + ": rotation quaternion has norm " + std::to_string(norm));
    quat.normalize();
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = quat.toRotationMatrix();
    T.translation() << t[0], t[1], t[2];
    return T;
  }

 private:
  std::string file_;
  json rows_;
};

std::string findTableDirectory(const std::string& dataroot, const std::string& version) {
  std::error_code ec;
  if (!fs::is_directory(dataroot, ec)) throw IoError(dataroot, "dataroot is not a directory");
  if (!version.empty()) {
    const fs::path dir = fs::path(dataroot) / version;
    if (!fs::is_directory(dir, ec)) throw IoError(dir.string(), "no such table directory (version '" + version + "')");
    return dir.string();
  }
  if (fs::exists(fs::path(dataroot) / "sensor.json", ec)) return dataroot;
  std::vector<std::string> candidates;
  for (const auto& entry : fs::directory_iterator(dataroot, ec))
    if (entry.is_directory(ec) && fs::exists(entry.path() / "sensor.json", ec))
      candidates.push_back(entry.path().string());
  std::sort(candidates.begin(), candidates.end());
  if (candidates.empty())
    throw IoError(dataroot, "no table directory (a subfolder such as v1.0-mini holding sensor.json)");
  if (candidates.size() > 1)
    throw IoError(dataroot, "several table directories (" + candidates.front() + ", " + candidates[1] +
                                ", ...): choose one with a version");
  return candidates.front();
}

/// A radar's calibration: its channel index and its pose on the vehicle.
struct Calibration {
  int channel;
  Eigen::Isometry3d pose;
  Eigen::Vector4d rotation;
};

/// The radar sensors' tokens with their channel index; `channels` gets their names in table order.
std::unordered_map<std::string, int> radarSensors(const Table& sensor, std::vector<std::string>& channels) {
  std::unordered_map<std::string, int> radar_sensor;  // sensor token → radar channel index
  for (std::size_t i = 0; i < sensor.size(); ++i) {
    if (sensor.str(i, "modality") != "radar") continue;
    radar_sensor[sensor.str(i, "token")] = static_cast<int>(channels.size());
    channels.push_back(sensor.str(i, "channel"));
  }
  if (channels.size() > 65535) throw IoError(sensor.file(), "more than 65535 radar channels");
  return radar_sensor;
}

/// The radars' calibrations by calibrated_sensor token (cameras and lidars left out).
std::unordered_map<std::string, Calibration> radarCalibrations(const Table& calibrated,
                                                               const std::unordered_map<std::string, int>& radars) {
  std::unordered_map<std::string, Calibration> calibration;
  for (std::size_t i = 0; i < calibrated.size(); ++i) {
    const auto it = radars.find(calibrated.str(i, "sensor_token"));
    if (it == radars.end()) continue;  // a camera or lidar
    calibration[calibrated.str(i, "token")] = {it->second, calibrated.pose(i), calibrated.rotation(i)};
  }
  return calibration;
}

/// The scenes, each with a log that log.json holds.
std::vector<NuScenesScene> readScenes(const Table& scene, const Table& log) {
  std::unordered_map<std::string, bool> logs;
  for (std::size_t i = 0; i < log.size(); ++i) logs[log.str(i, "token")] = true;
  std::vector<NuScenesScene> scenes;
  for (std::size_t i = 0; i < scene.size(); ++i) {
    NuScenesScene s;
    s.token = scene.str(i, "token");
    s.name = scene.str(i, "name");
    s.log_token = scene.str(i, "log_token");
    const auto d = scene.field(i, "description");
    s.description = d.is_string() ? d.get<std::string>() : "";
    if (!logs.count(s.log_token))
      throw IoError(scene.file(), "row " + std::to_string(i) + ": log_token '" + s.log_token + "' is not in log.json");
    scenes.push_back(s);
  }
  return scenes;
}

/// Row i's filename under the dataroot: a table may not point the reader at other files.
std::string sweepPath(const Table& sample_data, std::size_t i, const std::string& dataroot) {
  const std::string filename = sample_data.str(i, "filename");
  if (filename.empty()) throw IoError(sample_data.file(), "row " + std::to_string(i) + ": empty filename");
  const fs::path relative(filename);
  bool leaves = relative.has_root_name() || relative.has_root_directory() || filename.find('\0') != std::string::npos;
  for (const auto& part : relative)
    if (part == "..") leaves = true;
  if (leaves)
    throw IoError(sample_data.file(), "row " + std::to_string(i) + ": filename '" + filename +
                                          "' leaves the dataroot (an absolute path or '..'); sweeps must lie under it");
  return (fs::path(dataroot) / relative).string();
}

/// Looks `token` up in `index`, an IoError naming the row and the table it should be in otherwise.
template <typename Map>
typename Map::const_iterator lookUp(const Map& index, const std::string& token, const Table& table, std::size_t row,
                                    const char* column, const char* in) {
  const auto it = index.find(token);
  if (it == index.end())
    throw IoError(table.file(), "row " + std::to_string(row) + ": " + column + " '" + token + "' is not in " + in);
  return it;
}

}  // namespace

NuScenesDataset::NuScenesDataset(const std::string& dataroot, const std::string& version)
    : dataroot_(dataroot), table_dir_(findTableDirectory(dataroot, version)) {
  const Table sensor(table_dir_, "sensor"), calibrated(table_dir_, "calibrated_sensor"),
      sample_data(table_dir_, "sample_data"), ego_pose(table_dir_, "ego_pose"), sample(table_dir_, "sample"),
      scene(table_dir_, "scene"), log(table_dir_, "log");
  const auto calibration = radarCalibrations(calibrated, radarSensors(sensor, radar_channels_));
  std::unordered_map<std::string, std::size_t> ego_row;
  for (std::size_t i = 0; i < ego_pose.size(); ++i) ego_row[ego_pose.str(i, "token")] = i;
  std::unordered_map<std::string, std::string> sample_scene;
  for (std::size_t i = 0; i < sample.size(); ++i) sample_scene[sample.str(i, "token")] = sample.str(i, "scene_token");
  scenes_ = readScenes(scene, log);

  for (std::size_t i = 0; i < sample_data.size(); ++i) {
    const auto cal = calibration.find(sample_data.str(i, "calibrated_sensor_token"));
    if (cal == calibration.end()) continue;  // not a radar (or an unknown calibration: checked below for radars only)
    NuScenesSweep s;
    s.token = sample_data.str(i, "token");
    s.channel_index = static_cast<std::uint16_t>(cal->second.channel);
    s.channel = radar_channels_[s.channel_index];
    s.timestamp_us = sample_data.integer(i, "timestamp");
    s.is_key_frame = sample_data.boolean(i, "is_key_frame", false);
    s.path = sweepPath(sample_data, i, dataroot_);
    s.sensor_to_ego = cal->second.pose;
    s.sensor_rotation_wxyz = cal->second.rotation;
    const auto ego =
        lookUp(ego_row, sample_data.str(i, "ego_pose_token"), sample_data, i, "ego_pose_token", "ego_pose.json");
    s.ego_to_global = ego_pose.pose(ego->second);
    s.ego_rotation_wxyz = ego_pose.rotation(ego->second);
    const auto sc =
        lookUp(sample_scene, sample_data.str(i, "sample_token"), sample_data, i, "sample_token", "sample.json");
    sweeps_by_scene_[sc->second].push_back(std::move(s));
  }
  sortSweepsAndSpanScenes();
}

void NuScenesDataset::sortSweepsAndSpanScenes() {
  for (auto& [token, sweeps] : sweeps_by_scene_)
    std::sort(sweeps.begin(), sweeps.end(), [](const NuScenesSweep& a, const NuScenesSweep& b) {
      return a.timestamp_us != b.timestamp_us ? a.timestamp_us < b.timestamp_us : a.channel_index < b.channel_index;
    });
  for (auto& s : scenes_) {
    const auto it = sweeps_by_scene_.find(s.token);
    if (it == sweeps_by_scene_.end() || it->second.empty()) continue;
    s.first_timestamp_us = it->second.front().timestamp_us;
    s.last_timestamp_us = it->second.back().timestamp_us;
  }
}

const NuScenesScene& NuScenesDataset::scene(const std::string& name) const {
  for (const auto& s : scenes_)
    if (s.name == name || s.token == name) return s;
  std::string names;
  for (const auto& s : scenes_) names += (names.empty() ? "" : ", ") + s.name;
  throw std::invalid_argument("no scene '" + name + "' in " + table_dir_ + " (scenes: " + names + ")");
}

std::vector<NuScenesSweep> NuScenesDataset::radarSweeps(const NuScenesScene& scene) const {
  const auto it = sweeps_by_scene_.find(scene.token);
  return it == sweeps_by_scene_.end() ? std::vector<NuScenesSweep>{} : it->second;
}

}  // namespace radar_ndt

#include "radar_ndt/io/nuscenes_writer.h"

#include <cmath>
#include <cstring>
#include <sstream>

#include <nlohmann/json.hpp>

#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/nuscenes.h"

namespace radar_ndt {

int ars408RmsIndex(double sigma) {
  int best = 0;
  for (int i = 1; std::isfinite(ars408RmsValue(i)); ++i)
    if (std::abs(std::log(ars408RmsValue(i) / sigma)) < std::abs(std::log(ars408RmsValue(best) / sigma))) best = i;
  return best;
}

namespace {
template <typename T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}
}  // namespace

std::string nuScenesRadarPcdBytes(const std::vector<NuScenesRadarPoint>& points) {
  std::ostringstream h;
  h << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
       "FIELDS x y z dyn_prop id rcs vx vy vx_comp vy_comp is_quality_valid ambig_state x_rms y_rms invalid_state pdh0 "
       "vx_rms vy_rms\n"
       "SIZE 4 4 4 1 2 4 4 4 4 4 1 1 1 1 1 1 1 1\nTYPE F F F I I F F F F F I I I I I I I I\n"
       "COUNT 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1\n"
    << "WIDTH " << points.size() << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << points.size()
    << "\nDATA binary\n";
  std::string out = h.str();
  for (const NuScenesRadarPoint& p : points) {
    put(out, p.x);
    put(out, p.y);
    put(out, p.z);
    put(out, p.dyn_prop);
    put(out, p.id);
    put(out, p.rcs);
    put(out, p.vx);
    put(out, p.vy);
    put(out, p.vx_comp);
    put(out, p.vy_comp);
    put(out, p.is_quality_valid);
    put(out, p.ambig_state);
    put(out, p.x_rms);
    put(out, p.y_rms);
    put(out, p.invalid_state);
    put(out, p.pdh0);
    put(out, p.vx_rms);
    put(out, p.vy_rms);
  }
  return out;
}

void writeNuScenesRadarPcd(const std::string& path, const std::vector<NuScenesRadarPoint>& points) {
  writeFileAtomically(path, nuScenesRadarPcdBytes(points));
}

void NuScenesTableWriter::addLog(const std::string& token, const std::string& logfile, const std::string& vehicle,
                                 const std::string& date_captured, const std::string& location) {
  logs_.push_back({token, logfile, vehicle, date_captured, location});
}

void NuScenesTableWriter::addScene(const std::string& token, const std::string& log_token, std::size_t nbr_samples,
                                   const std::string& first_sample_token, const std::string& last_sample_token,
                                   const std::string& name, const std::string& description) {
  scenes_.push_back({token, log_token, nbr_samples, first_sample_token, last_sample_token, name, description});
}

void NuScenesTableWriter::addSample(const std::string& token, std::int64_t timestamp, const std::string& prev,
                                    const std::string& next, const std::string& scene_token) {
  samples_.push_back({token, timestamp, prev, next, scene_token});
}

void NuScenesTableWriter::addSensor(const std::string& token, const std::string& channel, const std::string& modality) {
  sensors_.push_back({token, channel, modality});
}

void NuScenesTableWriter::addCalibratedSensor(const std::string& token, const std::string& sensor_token,
                                              const std::array<double, 3>& translation,
                                              const std::array<double, 4>& rotation) {
  calibrations_.push_back({token, sensor_token, translation, rotation});
}

void NuScenesTableWriter::addEgoPose(const std::string& token, std::int64_t timestamp,
                                     const std::array<double, 4>& rotation, const std::array<double, 3>& translation) {
  ego_poses_.push_back({token, timestamp, rotation, translation});
}

void NuScenesTableWriter::addSampleData(const std::string& token, const std::string& sample_token,
                                        const std::string& ego_pose_token, const std::string& calibrated_sensor_token,
                                        std::int64_t timestamp, bool is_key_frame, const std::string& filename,
                                        const std::string& prev, const std::string& next) {
  sample_data_.push_back(
      {token, sample_token, ego_pose_token, calibrated_sensor_token, timestamp, is_key_frame, filename, prev, next});
}

void NuScenesTableWriter::write(const std::string& table_dir) const {
  using nlohmann::json;
  json logs = json::array(), scenes = json::array(), samples = json::array(), sensors = json::array(),
       calibrations = json::array(), ego_poses = json::array(), sample_data = json::array();
  for (const LogRow& r : logs_)
    logs.push_back({{"token", r.token},
                    {"logfile", r.logfile},
                    {"vehicle", r.vehicle},
                    {"date_captured", r.date_captured},
                    {"location", r.location}});
  for (const SceneRow& r : scenes_)
    scenes.push_back({{"token", r.token},
                      {"log_token", r.log_token},
                      {"nbr_samples", r.nbr_samples},
                      {"first_sample_token", r.first_sample_token},
                      {"last_sample_token", r.last_sample_token},
                      {"name", r.name},
                      {"description", r.description}});
  for (const SampleRow& r : samples_)
    samples.push_back({{"token", r.token},
                       {"timestamp", r.timestamp},
                       {"prev", r.prev},
                       {"next", r.next},
                       {"scene_token", r.scene_token}});
  for (const SensorRow& r : sensors_)
    sensors.push_back({{"token", r.token}, {"channel", r.channel}, {"modality", r.modality}});
  for (const CalibrationRow& r : calibrations_)
    calibrations.push_back({{"token", r.token},
                            {"sensor_token", r.sensor_token},
                            {"translation", r.translation},
                            {"rotation", r.rotation},
                            {"camera_intrinsic", json::array()}});
  for (const EgoPoseRow& r : ego_poses_)
    ego_poses.push_back(
        {{"token", r.token}, {"timestamp", r.timestamp}, {"rotation", r.rotation}, {"translation", r.translation}});
  for (const SampleDataRow& r : sample_data_)
    sample_data.push_back({{"token", r.token},
                           {"sample_token", r.sample_token},
                           {"ego_pose_token", r.ego_pose_token},
                           {"calibrated_sensor_token", r.calibrated_sensor_token},
                           {"timestamp", r.timestamp},
                           {"fileformat", "pcd"},
                           {"is_key_frame", r.is_key_frame},
                           {"height", 0},
                           {"width", 0},
                           {"filename", r.filename},
                           {"prev", r.prev},
                           {"next", r.next}});
  auto put_table = [&](const char* name, const json& j) {
    writeFileAtomically(table_dir + "/" + name + ".json", j.dump(1));
  };
  put_table("sensor", sensors);
  put_table("calibrated_sensor", calibrations);
  put_table("sample", samples);
  put_table("sample_data", sample_data);
  put_table("ego_pose", ego_poses);
  put_table("scene", scenes);
  put_table("log", logs);
}

}  // namespace radar_ndt

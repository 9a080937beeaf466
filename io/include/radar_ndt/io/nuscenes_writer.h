#pragma once
// Writing nuScenes-layout radar datasets: radar PCD files in the 18-field binary layout nuScenes
// uses, and the seven JSON tables NuScenesDataset reads (sensor, calibrated_sensor, sample,
// sample_data, ego_pose, scene, log). What radar_sim writes its automotive sequences with; the
// reader (nuscenes.h) reads them back unchanged.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace radar_ndt {

/// One detection as a nuScenes radar PCD stores it: sensor frame, the ARS408 fields as stored
/// (accuracies and states are the sensor's indices; ars408RmsValue decodes them).
struct NuScenesRadarPoint {
  float x = 0, y = 0, z = 0;
  std::int8_t dyn_prop = 1;  ///< 0 moving, 1 stationary, …
  std::int16_t id = 0;
  float rcs = 0;
  float vx = 0, vy = 0;            ///< velocity relative to the sensor (its radial part is the Doppler)
  float vx_comp = 0, vy_comp = 0;  ///< with the ego motion removed
  std::int8_t is_quality_valid = 1;
  std::int8_t ambig_state = 3;  ///< 3: unambiguous
  std::int8_t x_rms = 0, y_rms = 0;
  std::int8_t invalid_state = 0;  ///< 0: a valid cluster
  std::int8_t pdh0 = 1;
  std::int8_t vx_rms = 0, vy_rms = 0;
};

/// The ARS408 state index whose standard deviation (ars408RmsValue) is nearest, in log, to `sigma`.
int ars408RmsIndex(double sigma);

/// The bytes of a PCD v0.7 file with DATA binary and nuScenes' 18 radar fields.
std::string nuScenesRadarPcdBytes(const std::vector<NuScenesRadarPoint>& points);
/// Writes nuScenesRadarPcdBytes(points) to `path`, atomically. Throws IoError naming the file.
void writeNuScenesRadarPcd(const std::string& path, const std::vector<NuScenesRadarPoint>& points);

/// Rows of the seven tables, collected and then written as `<table_dir>/<table>.json`. Quaternions
/// are (w, x, y, z), as nuScenes stores them; timestamps are microseconds.
class NuScenesTableWriter {
 public:
  void addLog(const std::string& token, const std::string& logfile, const std::string& vehicle,
              const std::string& date_captured, const std::string& location);
  void addScene(const std::string& token, const std::string& log_token, std::size_t nbr_samples,
                const std::string& first_sample_token, const std::string& last_sample_token, const std::string& name,
                const std::string& description);
  void addSample(const std::string& token, std::int64_t timestamp, const std::string& prev, const std::string& next,
                 const std::string& scene_token);
  void addSensor(const std::string& token, const std::string& channel, const std::string& modality);
  void addCalibratedSensor(const std::string& token, const std::string& sensor_token,
                           const std::array<double, 3>& translation, const std::array<double, 4>& rotation);
  void addEgoPose(const std::string& token, std::int64_t timestamp, const std::array<double, 4>& rotation,
                  const std::array<double, 3>& translation);
  /// A radar sweep; `filename` is relative to the dataroot (samples/… or sweeps/…).
  void addSampleData(const std::string& token, const std::string& sample_token, const std::string& ego_pose_token,
                     const std::string& calibrated_sensor_token, std::int64_t timestamp, bool is_key_frame,
                     const std::string& filename, const std::string& prev, const std::string& next);

  /// Writes the seven tables into `table_dir` (which must exist), each atomically. Throws IoError
  /// naming the file.
  void write(const std::string& table_dir) const;

 private:
  struct LogRow {
    std::string token, logfile, vehicle, date_captured, location;
  };
  struct SceneRow {
    std::string token, log_token;
    std::size_t nbr_samples;
    std::string first_sample_token, last_sample_token, name, description;
  };
  struct SampleRow {
    std::string token;
    std::int64_t timestamp;
    std::string prev, next, scene_token;
  };
  struct SensorRow {
    std::string token, channel, modality;
  };
  struct CalibrationRow {
    std::string token, sensor_token;
    std::array<double, 3> translation;
    std::array<double, 4> rotation;
  };
  struct EgoPoseRow {
    std::string token;
    std::int64_t timestamp;
    std::array<double, 4> rotation;
    std::array<double, 3> translation;
  };
  struct SampleDataRow {
    std::string token, sample_token, ego_pose_token, calibrated_sensor_token;
    std::int64_t timestamp;
    bool is_key_frame;
    std::string filename, prev, next;
  };
  std::vector<LogRow> logs_;
  std::vector<SceneRow> scenes_;
  std::vector<SampleRow> samples_;
  std::vector<SensorRow> sensors_;
  std::vector<CalibrationRow> calibrations_;
  std::vector<EgoPoseRow> ego_poses_;
  std::vector<SampleDataRow> sample_data_;
};

}  // namespace radar_ndt

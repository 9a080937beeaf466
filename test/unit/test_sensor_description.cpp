#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;

namespace {

/// Expects an IoError naming `source`, the key and the problem, on `line` (0: any).
void expectError(const std::string& yaml, const std::string& key, const std::string& problem, std::size_t line = 0) {
  try {
    parseSensorDescription(yaml, "my_radar.yaml");
    ADD_FAILURE() << "expected an error for:\n" << yaml;
  } catch (const IoError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("my_radar.yaml"), std::string::npos) << msg;
    EXPECT_NE(msg.find(key), std::string::npos) << msg;
    EXPECT_NE(msg.find(problem), std::string::npos) << msg << " (wanted: " << problem << ")";
    if (line) {
      EXPECT_EQ(e.line(), line) << msg;
    }
  }
}

const char* const kMinimal = R"(
radars:
  - topic: /radar
    fields: {doppler: {radial: v}}
)";

}  // namespace

TEST(SensorDescription, AMinimalFileTakesTheDefaults) {
  const SensorDescription d = parseSensorDescription(kMinimal, "my_radar.yaml");
  ASSERT_EQ(d.radars.size(), 1u);
  const RadarDescription& r = d.radars[0];
  EXPECT_EQ(r.name, "/radar");  // named by its topic
  EXPECT_EQ(r.kind, RadarKind::PointCloud);
  EXPECT_FALSE(r.mounting);  // from the recording's TF
  EXPECT_EQ(r.fields.doppler, DopplerKind::Radial);
  EXPECT_EQ(r.fields.radial, "v");
  EXPECT_EQ(r.fields.radial_sign, 1.0);
  EXPECT_EQ(r.fields.accuracy, AccuracyKind::Model);
  EXPECT_EQ(r.fields.x, "x");
  EXPECT_EQ(d.stamps, StampSource::Auto);
  EXPECT_EQ(d.base_frame, "base_link");
  EXPECT_TRUE(d.imu_topic.empty());
  EXPECT_TRUE(d.ground_truth_topic.empty());
}

TEST(SensorDescription, EveryKeyIsRead) {
  const SensorDescription d = parseSensorDescription(R"(
name: my car
base_frame: vehicle
stamps: receive
imu: /imu/data
speed: /vehicle/twist
ground_truth: {topic: /gt, parent: world, child: vehicle}
reference: front
radars:
  - name: front
    topic: /front/points
    frame: front_radar
    mounting: {x: 3.5, y: -0.2, z: 0.6, yaw: 0.1}
    fields:
      position: [px, py]
      doppler: {radial: vr, sign: approaching}
      rcs: rcs_dbsm
      power: snr
      accuracy: {fixed: [0.25, 0.5]}
      max_range: 80
      keep: {quality: [1, 2]}
)",
                                                     "my_radar.yaml");
  EXPECT_EQ(d.name, "my car");
  EXPECT_EQ(d.base_frame, "vehicle");
  EXPECT_EQ(d.stamps, StampSource::Receive);
  EXPECT_EQ(d.imu_topic, "/imu/data");
  EXPECT_EQ(d.speed_topic, "/vehicle/twist");
  EXPECT_EQ(d.ground_truth_topic, "/gt");
  EXPECT_EQ(d.ground_truth_parent, "world");
  EXPECT_EQ(d.reference, "front");
  const RadarDescription& r = d.radars.at(0);
  EXPECT_EQ(r.frame, "front_radar");
  ASSERT_TRUE(r.mounting);
  EXPECT_NEAR(r.mounting->transform().translation().x(), 3.5, 0);
  EXPECT_NEAR(Eigen::AngleAxisd(r.mounting->transform().linear()).angle(), 0.1, 1e-12);
  EXPECT_EQ(r.fields.x, "px");
  EXPECT_EQ(r.fields.z, "");  // planar: no z field
  EXPECT_EQ(r.fields.radial_sign, -1.0);
  EXPECT_EQ(r.fields.rcs, "rcs_dbsm");
  EXPECT_EQ(r.fields.power, "snr");
  EXPECT_EQ(r.fields.accuracy, AccuracyKind::Fixed);
  EXPECT_EQ(r.fields.sigma_y, 0.5);
  EXPECT_EQ(r.fields.max_range, 80);
  ASSERT_EQ(r.fields.keep.size(), 1u);
  EXPECT_EQ(r.fields.keep[0].first, "quality");
  EXPECT_EQ(r.fields.keep[0].second, (std::vector<int>{1, 2}));
}

TEST(SensorDescription, ABadFileNamesTheKeyAndTheLine) {
  expectError("radars: [", "", "not valid YAML");
  expectError("", "", "empty");
  expectError("radar: []\n", "radar", "unknown key", 1);
  expectError("radars: []\n", "radars", "at least one radar");
  expectError("radars:\n  - fields: {doppler: none}\n", "radars[0]", "missing key 'topic'");
  expectError("radars:\n  - topic: /r\n", "radars[0]", "missing key 'fields'");
  expectError("radars:\n  - topic: /r\n    fields: {position: [x, y]}\n", "radars[0].fields", "missing key 'doppler'");
  expectError("radars:\n  - topic: /r\n    fields:\n      doppler: {radial: v, sign: up}\n",
              "radars[0].fields.doppler.sign", "'receding'", 4);
  expectError("radars:\n  - topic: /r\n    fields: {doppler: {vx: a}}\n", "radars[0].fields.doppler",
              "both 'vx' and 'vy'");
  expectError("radars:\n  - topic: /r\n    fields: {doppler: {radial: v}, max_range: -3}\n",
              "radars[0].fields.max_range", "> 0");
  expectError("radars:\n  - topic: /r\n    fields: {doppler: {radial: v}, max_range: far}\n",
              "radars[0].fields.max_range", "not a finite number");
  expectError("radars:\n  - topic: /r\n    fields: {doppler: {radial: v}, accuracy: {fixed: [0.1]}}\n",
              "radars[0].fields.accuracy.fixed", "list of two");
  expectError("radars:\n  - topic: /r\n    fields: {doppler: {radial: v}, keep: {q: [1.5]}}\n",
              "radars[0].fields.keep.q[0]", "not an integer");
  expectError("radars:\n  - topic: /r\n    mounting: {x: 1, yaww: 2}\n    fields: {doppler: {radial: v}}\n",
              "radars[0].mounting.yaww", "unknown key");
  expectError(
      "radars:\n  - {topic: /a, fields: {doppler: {radial: v}}}\n  - {topic: /a, name: b, fields: {doppler: {radial: "
      "v}}}\n",
      "radars[1]", "second radar on topic");
  expectError("radars:\n  - {name: !front, topic: /r, fields: {doppler: {radial: v}}}\n", "radars[0].name",
              "empty name");
  expectError("radars:\n  - topic: /r\n    fields: {doppler: {radial: v}, keep: {q: }}\n", "radars[0].fields.keep",
              "'q': expected a list");
  expectError(std::string(kMinimal) + "reference: rear\n", "reference", "none of the radars");
  expectError(std::string(kMinimal) + "stamps: gps\n", "stamps", "header, receive or auto");
  expectError(std::string(kMinimal) + "imu_mounting: {roll: up}\n", "imu_mounting.roll", "not a finite number");
}

// The IMU's mounting: an IMU upside down (roll π) reads the vehicle's left turn as a negative rate
// about its own z; NTU4DRadLM's preset describes its VectorNav so.
TEST(SensorDescription, AnImuMountingTurnsTheGyroIntoTheBaseFrame) {
  const SensorDescription plain = parseSensorDescription(kMinimal, "plain.yaml");
  EXPECT_FALSE(plain.imu_mounting);
  EXPECT_DOUBLE_EQ(imuYawRate(plain, Eigen::Vector3d(0.1, 0.2, 0.3)), 0.3);
  const SensorDescription flipped =
      parseSensorDescription(std::string(kMinimal) + "imu_mounting: {roll: 3.141592653589793}\n", "flipped.yaml");
  ASSERT_TRUE(flipped.imu_mounting);
  EXPECT_NEAR(imuYawRate(flipped, Eigen::Vector3d(0.1, 0.2, -0.3)), 0.3, 1e-12);
  EXPECT_TRUE((imuRotation(flipped) * Eigen::Vector3d(0, 0, -9.81)).isApprox(Eigen::Vector3d(0, 0, 9.81), 1e-12));
  const SensorDescription ntu = readSensorDescription("preset:ntu4dradlm_eagle");
  ASSERT_TRUE(ntu.imu_mounting);
  EXPECT_GT((imuRotation(ntu) * Eigen::Vector3d(0, 0, -9.81)).z(), 9.7);
  EXPECT_EQ(ntu.radars.at(0).fields.radial, "#0");
  EXPECT_EQ(ntu.radars.at(0).fields.power, "#2");
}

// Snail-Radar's ARS548: dataset_tools' Body_T_Ars548.m composes R3d(3) * R2d(1), passive rotations
// (R3d's comment: p_B = R3(θ) p_A for a frame B turned by θ about z, so R3(θ) = Rz(θ)ᵀ), here
// written out as those matrices, against the preset's roll, pitch and yaw.
TEST(SensorDescription, SnailRadarsArs548MountingIsTheDatasetsPassiveRotations) {
  const SensorDescription d = readSensorDescription("preset:snail_radar_ars548");
  ASSERT_EQ(d.radars.size(), 1u);
  const double a = 3.0 * kPi / 180.0, b = 1.0 * kPi / 180.0;
  Eigen::Matrix3d R3, R2;
  R3 << std::cos(a), std::sin(a), 0, -std::sin(a), std::cos(a), 0, 0, 0, 1;
  R2 << std::cos(b), 0, -std::sin(b), 0, 1, 0, std::sin(b), 0, std::cos(b);
  ASSERT_TRUE(d.radars[0].mounting);
  const Eigen::Isometry3d T = d.radars[0].mounting->transform();
  EXPECT_LT((T.linear() - R3 * R2).norm(), 1e-6);
  EXPECT_TRUE(T.translation().isApprox(Eigen::Vector3d(0, 0, 0.07)));
  // A detection straight ahead of the radar lies a little right of the body's x and above it: the
  // radar looks up, as the dataset says of the morning it was "tilted backward" (R2d(5)).
  const Eigen::Vector3d ahead = T.linear() * Eigen::Vector3d(10, 0, 0);
  EXPECT_LT(ahead.y(), 0.0);
  EXPECT_GT(ahead.z(), 0.0);
  EXPECT_EQ(d.radars[0].fields.radial, "doppler");
  EXPECT_EQ(d.radars[0].fields.rcs, "intensity");
  EXPECT_TRUE(d.radars[0].fields.power.empty());
  EXPECT_EQ(d.imu_topic, "/x36d/imu_raw");
  EXPECT_FALSE(d.imu_mounting);
}

// A scanning radar: its polar image's layout read, and what does not apply to it refused.
TEST(SensorDescription, AScanningRadarIsDescribedByItsPolarImage) {
  const SensorDescription d = parseSensorDescription(
      "radars:\n  - topic: /Navtech/Polar\n    kind: scanning\n    polar: {rows: range, range_resolution: 0.175, "
      "range_offset_bins: 0, azimuth_zero: 1.5, azimuth_offset: 0.5, clockwise: false, stamp: end, sweep_period: "
      "0.25, max_range: 100}\n",
      "t.yaml");
  ASSERT_EQ(d.radars.size(), 1u);
  const PolarImageDescription& p = d.radars[0].polar;
  EXPECT_EQ(d.radars[0].kind, RadarKind::Scanning);
  EXPECT_FALSE(p.rows_are_azimuths);
  EXPECT_EQ(p.convention.range_resolution, 0.175);
  EXPECT_EQ(p.convention.range_offset_bins, 0.0);
  EXPECT_EQ(p.convention.azimuth_zero, 1.5);
  EXPECT_FALSE(p.convention.clockwise);
  EXPECT_EQ(p.azimuth_offset, 0.5);
  EXPECT_EQ(p.stamp_position, 1.0);
  EXPECT_EQ(p.sweep_period, 0.25);
  EXPECT_EQ(p.max_range, 100.0);
  const std::string head = "radars:\n  - topic: /p\n    kind: scanning\n";
  expectError(head, "radars[0]", "missing key 'polar'");
  expectError(head + "    polar: {range_resolution: 0.04}\n", "radars[0].polar", "missing key 'rows'");
  expectError(head + "    polar: {rows: bearing, range_resolution: 0.04}\n", "radars[0].polar.rows", "azimuth");
  expectError(head + "    polar: {rows: azimuth}\n", "radars[0].polar", "range_resolution");
  expectError(head + "    polar: {rows: azimuth, range_resolution: 0}\n", "radars[0].polar.range_resolution", "> 0");
  expectError(head + "    polar: {rows: azimuth, range_resolution: 0.04, stamp: late}\n", "radars[0].polar.stamp",
              "start, middle or end");
  expectError(head + "    polar: {rows: azimuth, range_resolution: 0.04, clockwise: yes}\n",
              "radars[0].polar.clockwise", "true");
  expectError(head + "    mounting: {x: 1}\n    polar: {rows: azimuth, range_resolution: 0.04}\n", "radars[0].mounting",
              "the radar's own");
  expectError(head + "    fields: {doppler: none}\n    polar: {rows: azimuth, range_resolution: 0.04}\n",
              "radars[0].fields", "not point fields");
  expectError("radars:\n  - topic: /r\n    fields: {doppler: none}\n    polar: {rows: azimuth}\n", "radars[0].polar",
              "kind: scanning");
  expectError(head + "    polar: {rows: azimuth, range_resolution: 0.04}\n  - {topic: /q, fields: {doppler: none}}\n",
              "radars", "run alone");
}

TEST(SensorDescription, AMissingFileOrPresetIsNamed) {
  EXPECT_THROW(readSensorDescription(::testing::TempDir() + "no_such.yaml"), IoError);
  try {
    readSensorDescription("preset:no_such_radar");
    ADD_FAILURE();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("nuscenes_ars408"), std::string::npos) << e.what();  // lists the presets
  }
}

// Every preset reads; the nuScenes one describes exactly what the nuScenes PCD reader keeps, so a
// bag of a scene gives the scene's detections.
TEST(SensorDescription, ThePresetsReadAndTheNuScenesOneIsTheReadersFields) {
  const std::vector<std::string> presets = sensorPresets();
  ASSERT_GE(presets.size(), 2u) << sensorPresetDirectory();
  for (const std::string& p : presets) EXPECT_NO_THROW(readSensorDescription("preset:" + p)) << p;
  const SensorDescription d = readSensorDescription("preset:nuscenes_ars408");
  ASSERT_EQ(d.radars.size(), 5u);
  const RadarPointFields ref = nuScenesArs408Fields(NuScenesRadarFilter{});
  for (const RadarDescription& r : d.radars) {
    const auto cols = r.fields.columns(), ref_cols = ref.columns();
    EXPECT_EQ(std::vector<std::string>(cols.begin(), cols.begin() + 8),
              std::vector<std::string>(ref_cols.begin(), ref_cols.begin() + 8))
        << r.name;
    EXPECT_EQ(r.fields.max_range, ref.max_range);
    EXPECT_EQ(r.fields.accuracy, AccuracyKind::Ars408Rms);
    // dyn_prop and ambig_state keep all: left out of the preset.
    ASSERT_EQ(r.fields.keep.size(), 1u);
    EXPECT_EQ(r.fields.keep[0], ref.keep[0]);
    EXPECT_TRUE(ref.keep[1].second.empty() && ref.keep[2].second.empty());
    EXPECT_EQ(r.fields.keep_doppler, ref.keep_doppler);
    EXPECT_EQ(r.topic, "/" + r.name);
  }
  EXPECT_EQ(d.radars[0].name, "RADAR_FRONT");  // sensor.json's order: the channel indices agree
}

// The conversion of named fields: Doppler from a radial field with either sign, or from the
// velocity's components; the accuracy models; the keep lists; NaN points dropped.
TEST(SensorDescription, RadarPointsFromNamedFields) {
  RadarPointFields f;
  f.z = "";
  f.doppler = DopplerKind::Radial;
  f.radial = "v";
  f.accuracy = AccuracyKind::Fixed;
  f.sigma_x = 0.2;
  f.sigma_y = 0.4;
  f.keep = {{"q", {1}}};
  ASSERT_EQ(f.columns(), (std::vector<std::string>{"x", "y", "", "v", "q"}));
  const std::vector<double> table{3,   4, 0, 2.0, 1,   // kept
                                  3,   4, 0, 2.0, 0,   // dropped by q
                                  NAN, 4, 0, 1,   1,   // dropped: not finite
                                  300, 0, 0, 1,   1};  // beyond 150 m
  RadarPointStats stats;
  auto cloud = convertRadarPoints(table, 4, {1, 1, 0, 1, 1}, f, 7, &stats);
  ASSERT_EQ(cloud.size(), 1u);
  EXPECT_EQ(cloud[0].doppler, 2.0f);
  EXPECT_EQ(cloud[0].z, 0.0f);
  EXPECT_EQ(cloud[0].sensor_id, 7);
  EXPECT_FLOAT_EQ(cloud[0].cov_yy, 0.16f);
  EXPECT_EQ(stats.dropped_non_finite, 1u);
  EXPECT_EQ(stats.dropped_by_filter, 2u);
  f.radial_sign = -1.0;  // a driver whose approaching targets are positive
  EXPECT_EQ(convertRadarPoints(table, 1, {1, 1, 0, 1, 1}, f, 0)[0].doppler, -2.0f);
  // The velocity's components: the radial part along the ray (3, 4)/5.
  f.doppler = DopplerKind::Components;
  f.keep.clear();
  f.accuracy = AccuracyKind::Model;
  ASSERT_EQ(f.columns(), (std::vector<std::string>{"x", "y", "", "vx", "vy"}));
  cloud = convertRadarPoints({3, 4, 0, 1, 2}, 1, {1, 1, 0, 1, 1}, f, 0);
  EXPECT_FLOAT_EQ(cloud[0].doppler, (3 * 1 + 4 * 2) / 5.0f);
  EXPECT_EQ(cloud[0].cov_xx, 0.0f);  // the front-end's model
}

// A driver's per-point time: `time: FIELD` (seconds) or `{field, unit}`, read into time_offset (s)
// relative to the message's stamp; a named time field is required, a non-finite time dropped.
TEST(SensorDescription, APerPointTimeIsReadInSeconds) {
  const SensorDescription d = parseSensorDescription(
      "radars:\n  - {name: a, topic: /a, fields: {doppler: {radial: v}, time: {field: t, unit: ns}}}\n"
      "  - {name: b, topic: /b, fields: {doppler: {radial: v}, time: dt}}\n",
      "my_radar.yaml");
  EXPECT_EQ(d.radars[0].fields.time, "t");
  EXPECT_EQ(d.radars[0].fields.time_scale, 1e-9);
  EXPECT_EQ(d.radars[1].fields.time, "dt");
  EXPECT_EQ(d.radars[1].fields.time_scale, 1.0);
  expectError("radars:\n  - topic: /r\n    fields: {doppler: {radial: v}, time: {field: t, unit: min}}\n",
              "radars[0].fields.time.unit", "unknown unit 'min'");
  expectError("radars:\n  - topic: /r\n    fields: {doppler: {radial: v}, time: {unit: s}}\n", "radars[0].fields.time",
              "missing key 'field'");

  RadarPointFields f = d.radars[0].fields;
  ASSERT_EQ(f.columns(), (std::vector<std::string>{"x", "y", "z", "v", "t"}));
  EXPECT_EQ(f.requiredColumns(), (std::vector<std::string>{"x", "y", "v", "t"}));
  const std::vector<double> table{3, 4, 0, 1, -25e6,  // 25 ms before the stamp
                                  3, 4, 0, 1, NAN};
  RadarPointStats stats;
  const auto cloud = convertRadarPoints(table, 2, {1, 1, 1, 1, 1}, f, 0, &stats);
  ASSERT_EQ(cloud.size(), 1u);
  EXPECT_FLOAT_EQ(cloud[0].time_offset, -0.025f);
  EXPECT_EQ(stats.dropped_non_finite, 1u);
  f.time.clear();  // none named: every detection at the stamp
  EXPECT_EQ(convertRadarPoints({3, 4, 0, 1}, 1, {1, 1, 1, 1}, f, 0)[0].time_offset, 0.0f);
}

// The 4D radar simulator (radar_ndt/sim/radar_4d.h): its presets, the field of view and ranges of
// a scan, the Doppler's sign, each detection's covariance, and a scan-to-map pair's truth.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/sim/radar_4d.h"

using namespace radar_ndt;
using namespace radar_ndt::sim;

TEST(Radar4D, PresetsAndUnknownNames) {
  for (const auto& name : radar4DPresetNames()) EXPECT_EQ(radar4DPreset(name).name, name);
  EXPECT_THROW(radar4DPreset("ars408"), std::invalid_argument);
}

// Each preset names the description its driver's recordings are read with, and that description's
// point accuracy is the preset's (what the simulated bags and the 6-DoF table rely on).
TEST(Radar4D, EachPresetIsReadWithItsSensorDescription) {
  for (const std::string& name : radar4DPresetNames()) {
    const SensorDescription d = readSensorDescription("preset:" + radar4DSensorPreset(name));
    ASSERT_EQ(d.radars.size(), 1u) << name;
    ASSERT_TRUE(d.radars[0].fields.spherical.has_value()) << name;
    const SphericalAccuracy a = radar4DPreset(name).accuracy;
    EXPECT_DOUBLE_EQ(d.radars[0].fields.spherical->range, a.range_sigma) << name;
    EXPECT_DOUBLE_EQ(d.radars[0].fields.spherical->azimuth_deg, a.azimuth_sigma_deg) << name;
    EXPECT_DOUBLE_EQ(d.radars[0].fields.spherical->elevation_deg, a.elevation_sigma_deg) << name;
  }
  EXPECT_EQ(radar4DSensorPreset("ars548"), "snail_radar_ars548");
  EXPECT_THROW(radar4DSensorPreset("ars408"), std::invalid_argument);
}

TEST(Radar4D, ScanStaysInItsFieldOfViewWithDopplerOfTheSensorsMotion) {
  const World3D world = streetWorld(200, 3);
  Radar4DModel m = radar4DPreset("oculii_eagle");
  m.false_alarms = 0;
  m.ghost_fraction = 0;
  Pose3 pose = Pose3::Identity();
  pose.translation() << 20, 0, 0.8;
  const Eigen::Vector3d velocity(10, 0, 0);  // forward at 10 m/s
  const auto scan = simulateScan4D(world, pose, velocity, m, 1, 0);
  ASSERT_GT(scan.size(), 500u);
  const double deg = kPi / 180.0;
  for (const auto& p : scan) {
    const Eigen::Vector3d v(p.x, p.y, p.z);
    const double r = v.norm(), az = std::atan2(v.y(), v.x()), el = std::asin(v.z() / r);
    EXPECT_LE(r, m.max_range + 1.0);
    EXPECT_LE(std::abs(az), 0.5 * m.azimuth_fov_deg * deg + 0.05);
    EXPECT_LE(std::abs(el), 0.5 * m.elevation_fov_deg * deg + 0.1);
    // A static world seen from a sensor moving forward closes in: negative radial velocity (the
    // convention: positive when the target recedes), −v·u up to the Doppler noise.
    EXPECT_NEAR(p.doppler, -velocity.dot(v / r), 5 * m.doppler_sigma + 0.05);
    EXPECT_GT(p.cov_zz, 0.f);
  }
  // The same seed and stream give the same scan.
  EXPECT_EQ(simulateScan4D(world, pose, velocity, m, 1, 0).size(), scan.size());
}

TEST(Radar4D, PairTruthPlacesTheSourceOnTheMap) {
  ScanToMapOptions o;
  o.preset = "ars548";
  o.noise_scale = 0.01;
  const ScanToMapPair pair = scanToMapPair(o, 5, 0);
  ASSERT_FALSE(pair.source.empty());
  ASSERT_FALSE(pair.map.empty());
  // The guess is off by the asked translation and rotation.
  EXPECT_NEAR((pair.guess.translation() - pair.truth.translation()).norm(), o.translation_error, 1e-9);
  EXPECT_NEAR(Eigen::AngleAxisd(pair.guess.linear() * pair.truth.linear().transpose()).angle(), o.rotation_error, 1e-9);
  // Near-noiseless: most source points, placed by the truth, lie close to some map point.
  int close = 0;
  for (const auto& p : pair.source) {
    const Eigen::Vector3d q = pair.truth * Eigen::Vector3d(p.x, p.y, p.z);
    double best = 1e9;
    for (const auto& m : pair.map) best = std::min(best, (q - Eigen::Vector3d(m.x, m.y, m.z)).norm());
    if (best < 1.0) ++close;
  }
  EXPECT_GT(close, static_cast<int>(0.8 * pair.source.size()));
}

TEST(Radar4D, ADriversThresholdLeavesNoWeakDetectionAndThinsTheFarOnes) {
  // The TI preset reports only what its driver's CFAR threshold passes (min_snr): no detection
  // under it, and, as the SNR falls with range, fewer far detections than the same radar without it.
  const World3D world = corridorWorld(4);
  Pose3 pose = Pose3::Identity();
  pose.translation() << -20, -18.8, 1.3;  // in the south corridor, looking along it
  const Radar4DModel m = radar4DPreset("ti_iwr6843_rio");
  ASSERT_GT(m.min_snr, 0.0);
  Radar4DModel open = m;
  open.min_snr = 0;
  std::size_t far = 0, far_open = 0, points = 0;
  for (std::uint64_t k = 0; k < 50; ++k) {
    for (const auto& p : simulateScan4D(world, pose, Eigen::Vector3d(1, 0, 0), m, 2, k)) {
      EXPECT_GE(p.power, m.min_snr);
      far += Eigen::Vector3d(p.x, p.y, p.z).norm() > 8.0;
      ++points;
    }
    for (const auto& p : simulateScan4D(world, pose, Eigen::Vector3d(1, 0, 0), open, 2, k))
      far_open += Eigen::Vector3d(p.x, p.y, p.z).norm() > 8.0;
  }
  EXPECT_GT(points, 50u * 10);
  EXPECT_LT(far, far_open);
}

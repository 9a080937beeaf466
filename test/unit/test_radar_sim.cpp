// radar_sim: determinism, motion distortion, occlusion, realism against the real RADIATE scans,
// and the automotive dataroot read back by the nuScenes reader.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include <gtest/gtest.h>

#include "radar_ndt/evaluation/scan_statistics.h"
#include "radar_ndt/frontend/power_threshold.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/io/oxford_ground_truth.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/io/radiate_scan.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/pipeline/scanning_sequence.h"
#include "radar_ndt/sim/radar_sim.h"
#include "test_support.h"

using namespace radar_ndt;
using radar_ndt::test::freshTempDir;
using radar_ndt::test::readBytes;
namespace fs = std::filesystem;

namespace {

/// Straight drive along +x at `speed` m/s for 10 s.
sim::SimTrajectory straight(double speed) {
  std::vector<double> t;
  std::vector<Pose2> p;
  for (int k = 0; k <= 40; ++k) {
    t.push_back(0.25 * k);
    p.emplace_back(speed * 0.25 * k, 0.0, 0.0);
  }
  return sim::SimTrajectory(t, p);
}

/// The radiate profile's sensor (the plain log display these geometric checks were written for),
/// with no random artefacts (ghosts, saturation lines, ground clutter). The geometry (ray casting,
/// per-azimuth timing) is the same code for every profile.
sim::ScanningOptions radiate() {
  sim::WorldOptions w;
  sim::ScanningOptions o;
  sim::applyProfile(sim::ScanningProfile::Radiate, w, o);
  return o;
}
sim::ScanningOptions clean() {
  sim::ScanningOptions o = radiate();
  o.ghost_probability = 0.0;
  o.saturation_probability = 0.0;
  o.ground_clutter_cover = 0.0;
  return o;
}

/// Range (m) of the leading edge of the strongest return along azimuth `a` between `lo` and `hi`
/// metres: the first bin above half way from the noise floor to the peak (a surface returns from
/// its front face over its depth, so the edge, not the peak, is where it is).
double edgeRange(const PolarScan& s, int a, double lo, double hi) {
  int best = -1, first = -1;
  double floor = 0;
  int n = 0;
  for (int b = 0; b < s.bins; ++b) {
    const double r = s.rangeOf(b);
    if (r < lo || r > hi) continue;
    if (first < 0) first = b;
    floor += s.row(a)[b];
    ++n;
    if (best < 0 || s.row(a)[b] > s.row(a)[best]) best = b;
  }
  floor /= n;
  const double half = 0.5 * (floor + s.row(a)[best]);
  int b = best;
  while (b > first && s.row(a)[b - 1] > half) --b;
  return s.rangeOf(b);
}

/// Mean pixel value along azimuth `a` within [lo, hi] m.
double meanPower(const PolarScan& s, int a, double lo, double hi) {
  double sum = 0;
  int n = 0;
  for (int b = 0; b < s.bins; ++b) {
    const double r = s.rangeOf(b);
    if (r < lo || r > hi) continue;
    sum += s.row(a)[b];
    ++n;
  }
  return sum / n / 255.0;
}

}  // namespace

TEST(RadarSim, DeterministicForASeed) {
  const sim::SimTrajectory ego = sim::builtinDrive(40.0);
  sim::WorldOptions wo;
  wo.seed = 3;
  const sim::World w1 = sim::World::generate(ego, wo), w2 = sim::World::generate(ego, wo);
  EXPECT_EQ(w1.segments().size(), w2.segments().size());
  EXPECT_GT(w1.segments().size(), 100u);
  EXPECT_GT(w1.circles().size(), 10u);
  EXPECT_FALSE(w1.movers().empty());
  PolarScan a, b, c, d;
  sim::renderScan(w1, ego, 20.0, 3, 5, sim::ScanningOptions(), a);
  sim::renderScan(w2, ego, 20.0, 3, 5, sim::ScanningOptions(), b);
  EXPECT_EQ(a.power, b.power);
  // A frame does not depend on what was rendered before it; another frame number or seed differs.
  sim::renderScan(w1, ego, 20.0, 3, 6, sim::ScanningOptions(), c);
  EXPECT_NE(a.power, c.power);
  sim::renderScan(w1, ego, 20.0, 3, 5, sim::ScanningOptions(), d);
  EXPECT_EQ(a.power, d.power);
  wo.seed = 4;
  const sim::World w3 = sim::World::generate(ego, wo);
  EXPECT_NE(w3.segments().size() + 1000 * w3.circles().size(), w1.segments().size() + 1000 * w1.circles().size());

  // Whole sequences: byte-identical files.
  const std::string d1 = freshTempDir("sim_det1"), d2 = freshTempDir("sim_det2");
  sim::SequenceOptions seq;
  seq.start = 40;
  seq.frames = 3;
  wo.seed = 3;
  sim::writeScanningSequence(d1, ego, wo, sim::ScanningOptions(), seq);
  sim::writeScanningSequence(d2, ego, wo, sim::ScanningOptions(), seq);
  for (const char* f : {"radar.timestamps", "gt/radar_odometry.csv", "gt/poses.txt", "radar/1547120000250000.png"})
    EXPECT_EQ(readBytes(d1 + "/" + f), readBytes(d2 + "/" + f)) << f;
  EXPECT_FALSE(readBytes(d1 + "/radar/1547120000250000.png").empty());
  fs::remove_all(d1);
  fs::remove_all(d2);
}

TEST(RadarSim, MirroredWorldIsTheSeedsWorldMirroredAcrossThePath) {
  // On a straight path along x the mirror is y -> -y: every segment, circle and mover lane of the
  // seed's world, with the same draws (what `--set mirror=1` gives for an experiment).
  const sim::SimTrajectory ego = straight(10.0);
  sim::WorldOptions wo;
  wo.seed = 5;
  const sim::World w = sim::World::generate(ego, wo);
  wo.mirror = 1;
  const sim::World m = sim::World::generate(ego, wo);
  ASSERT_EQ(w.segments().size(), m.segments().size());
  ASSERT_EQ(w.circles().size(), m.circles().size());
  ASSERT_EQ(w.movers().size(), m.movers().size());
  ASSERT_GT(w.segments().size(), 20u);
  const Eigen::Vector2d flip(1.0, -1.0);
  int left = 0;  // segment i is the mirror of segment i (each keeps its index: ghosts are drawn by index)
  for (std::size_t i = 0; i < w.segments().size(); ++i) {
    const sim::Segment &a = w.segments()[i], &b = m.segments()[i];
    EXPECT_EQ(a.material, b.material) << i;
    EXPECT_LT((b.a - a.a.cwiseProduct(flip)).norm(), 1e-9) << i;
    EXPECT_LT((b.b - a.b.cwiseProduct(flip)).norm(), 1e-9) << i;
    left += a.a.y() > 0;
  }
  EXPECT_GT(left, 0);
  EXPECT_LT(left, static_cast<int>(w.segments().size())) << "both sides are built";
  for (std::size_t i = 0; i < w.circles().size(); ++i) {
    EXPECT_LT((m.circles()[i].c - w.circles()[i].c.cwiseProduct(flip)).norm(), 1e-9) << i;
    EXPECT_EQ(m.circles()[i].r, w.circles()[i].r) << i;
  }
  for (std::size_t i = 0; i < w.movers().size(); ++i) EXPECT_EQ(m.movers()[i].lateral, -w.movers()[i].lateral) << i;
  wo.mirror = 0.5;
  EXPECT_THROW(sim::World::generate(ego, wo), std::invalid_argument);
}

TEST(RadarSim, MotionDistortion) {
  // Walls across the road 20 m ahead and 20 m behind the start; the ego drives at 10 m/s.
  const sim::SimTrajectory ego = straight(10.0);
  const sim::World w = sim::World::fromPrimitives(
      ego, {{{20, -30}, {20, 30}, sim::Material::Building}, {{-20, -30}, {-20, 30}, sim::Material::Building}}, {});
  PolarScan s;
  sim::renderScan(w, ego, 0.0, 1, 0, clean(), s);
  // Azimuth timestamps spread over the sweep.
  EXPECT_EQ(s.stamp_us.back() - s.stamp_us.front(), 249375);
  for (int a = 1; a < s.azimuths; ++a) EXPECT_GT(s.stamp_us[a], s.stamp_us[a - 1]);
  // Azimuth 0 (t = 0): the front wall at 20 m; azimuth 200 (behind, t = 0.125 s, ego at 1.25 m):
  // the rear wall at 21.25 m; azimuth 399 (front again, t ≈ 0.249 s): the front wall at ≈ 17.5 m.
  EXPECT_NEAR(edgeRange(s, 0, 5, 40), 20.0,
              0.3);  // speckle and the facade's depth blur the edge; the effect is 1.25–2.5 m
  EXPECT_NEAR(edgeRange(s, 200, 5, 40), 21.25,
              0.3);  // speckle and the facade's depth blur the edge; the effect is 1.25–2.5 m
  EXPECT_NEAR(edgeRange(s, 399, 5, 40), 20.0 - 10.0 * 0.249375,
              0.3);  // speckle and the facade's depth blur the edge; the effect is 1.25–2.5 m
  // Standing still: no distortion.
  const sim::SimTrajectory still = straight(0.0 + 1e-9);
  const sim::World w0 = sim::World::fromPrimitives(
      still, {{{20, -30}, {20, 30}, sim::Material::Building}, {{-20, -30}, {-20, 30}, sim::Material::Building}}, {});
  sim::renderScan(w0, still, 0.0, 1, 0, clean(), s);
  EXPECT_NEAR(edgeRange(s, 399, 5, 40), 20.0,
              0.3);  // speckle and the facade's depth blur the edge; the effect is 1.25–2.5 m
  EXPECT_NEAR(edgeRange(s, 200, 5, 40), 20.0,
              0.3);  // speckle and the facade's depth blur the edge; the effect is 1.25–2.5 m
}

TEST(RadarSim, OcclusionAndTransmission) {
  const sim::SimTrajectory ego = straight(1e-9);
  // A facade 10 m ahead hides one 25 m ahead; off to the side (no facade in front) a pole at the
  // same range shows.
  const double side_angle = 36 * kPi / 180;
  const sim::World w = sim::World::fromPrimitives(
      ego, {{{10, -3}, {10, 3}, sim::Material::Building}, {{25, -5}, {25, 5}, sim::Material::Building}},
      {{{25 * std::cos(side_angle), 25 * std::sin(side_angle)}, 0.12, sim::Material::Pole}});
  PolarScan s;
  sim::renderScan(w, ego, 0.0, 1, 0, clean(), s);
  const double noise = meanPower(s, 0, 40, 60);
  EXPECT_GT(meanPower(s, 0, 9.8, 10.4), noise + 0.3);    // the near facade
  EXPECT_LT(meanPower(s, 0, 24.8, 25.4), noise + 0.03);  // hidden
  const int side = 400 - 40;                             // 36° to the left
  EXPECT_NEAR(edgeRange(s, side, 5, 60), 25.0 - 0.12, 0.2);
  EXPECT_GT(meanPower(s, side, 24.7, 25.1), noise + 0.2);
  // A tree crown lets part of the beam through: the facade behind it still shows, weaker.
  const sim::World t = sim::World::fromPrimitives(ego, {{{25, -40}, {25, 40}, sim::Material::Building}},
                                                  {{{12, 0}, 2.0, sim::Material::Crown}});
  PolarScan behind_tree, open;
  sim::renderScan(t, ego, 0.0, 1, 0, clean(), behind_tree);
  const sim::World o = sim::World::fromPrimitives(ego, {{{25, -40}, {25, 40}, sim::Material::Building}}, {});
  sim::renderScan(o, ego, 0.0, 1, 0, clean(), open);
  const double through = meanPower(behind_tree, 0, 24.8, 25.6), clear = meanPower(open, 0, 24.8, 25.6);
  EXPECT_GT(through, noise + 0.1);
  EXPECT_LT(through, clear);
  EXPECT_GT(meanPower(behind_tree, 0, 9.5, 14.0), noise + 0.05);  // the crown itself returns
}

TEST(RadarSim, BeamSmearsAPoleAcrossAzimuths) {
  const sim::SimTrajectory ego = straight(1e-9);
  const sim::World w = sim::World::fromPrimitives(ego, {}, {{{30, 0}, 0.12, sim::Material::Pole}});
  PolarScan s;
  sim::renderScan(w, ego, 0.0, 1, 0, clean(), s);
  const double noise = meanPower(s, 100, 20, 40);
  int lit = 0;
  for (int a : {398, 399, 0, 1, 2}) lit += meanPower(s, a, 29.8, 30.3) > noise + 0.1;
  EXPECT_GE(lit, 3);                                      // 2° beam over 0.9° azimuth steps
  EXPECT_LT(meanPower(s, 10, 29.8, 30.3), noise + 0.05);  // 9° off: dark
}

TEST(RadarSim, DisplayCompressionOnlyLowersReturnsAboveTheKnee) {
  const sim::SimTrajectory ego = straight(5.0);
  const sim::World w = sim::World::fromPrimitives(ego, {{{20, -10}, {20, 10}, sim::Material::Building}}, {});
  sim::ScanningOptions plain = clean(), compressed = clean();
  plain.display_compression = 1.0;
  compressed.display_compression = 0.35;
  compressed.display_knee_db = 10.0;
  PolarScan a, b;
  sim::renderScan(w, ego, 1.0, 1, 0, plain, a);
  sim::renderScan(w, ego, 1.0, 1, 0, compressed, b);
  ASSERT_EQ(a.power.size(), b.power.size());
  // Same random draws: a pixel at or below the knee's display value is unchanged; above it, the
  // displayed excess shrinks to 0.35 of itself (within the 8-bit rounding).
  const double knee = 255.0 * (plain.noise_display_level + 10.0 / plain.display_db_range);
  int above = 0, peak_a = 0, peak_b = 0;
  for (std::size_t i = 0; i < a.power.size(); ++i) {
    peak_a = std::max<int>(peak_a, a.power[i]);
    peak_b = std::max<int>(peak_b, b.power[i]);
    if (a.power[i] < knee - 0.5) {
      ASSERT_EQ(a.power[i], b.power[i]) << "pixel " << i;
    } else if (a.power[i] > knee + 0.5 && a.power[i] < 255) {
      ++above;
      EXPECT_NEAR(b.power[i], knee + 0.35 * (a.power[i] - knee), 1.0) << "pixel " << i;
    }
  }
  EXPECT_GT(above, 100);   // the facade
  EXPECT_GT(peak_a, 200);  // plain: a facade at 20 m lights up almost to full scale
  EXPECT_LT(peak_b, 0.75 * peak_a);
  sim::ScanningOptions bad = clean();
  bad.display_compression = 0.0;
  EXPECT_THROW(sim::renderScan(w, ego, 1.0, 1, 0, bad, b), std::invalid_argument);
}

TEST(RadarSim, RealismAgainstRadiate) {
  // The realism target, at a looser margin than the ±30 % docs/simulator.md measures on 10 scans.
  const std::string dir = std::string(RADAR_NDT_SHARED_DATA) + "/radiate-tiny-foggy/Navtech_Polar";
  if (!fs::exists(dir)) GTEST_SKIP() << "no " << dir << " (../shared/data is absent): skipping the realism check";
  const PowerThreshold front;
  std::vector<PowerStatistics> real;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".png")
      real.push_back(powerStatistics(front.cartesianImage(readRadiatePolarPng(e.path().string())), 0.333f));
  const PowerStatistics r = medianStatistics(real);
  const sim::SimTrajectory ego = sim::builtinDrive(120.0);
  sim::WorldOptions wo;
  const sim::World w = sim::World::generate(ego, wo);
  auto simulate = [&](const sim::ScanningOptions& options) {
    std::vector<PowerStatistics> simulated;
    PolarScan s;
    for (int k = 0; k < 5; ++k) {
      sim::renderScan(w, ego, 20.0 + 20.0 * k, wo.seed, k, options, s);
      simulated.push_back(powerStatistics(front.cartesianImage(s), 0.333f));
    }
    return medianStatistics(simulated);
  };
  auto expectPixelStatistics = [&](const PowerStatistics& m) {
    EXPECT_NEAR(m.fraction_above / r.fraction_above, 1.0, 0.4);
    EXPECT_NEAR(m.p50 / r.p50, 1.0, 0.4);
    EXPECT_NEAR(m.p90 / r.p90, 1.0, 0.4);
    EXPECT_NEAR(m.p99 / r.p99, 1.0, 0.4);
    EXPECT_GT(m.points, r.points / 3);
    EXPECT_LT(m.points, r.points * 3);
  };
  {
    SCOPED_TRACE("the radiate profile");
    const PowerStatistics m = simulate(radiate());
    expectPixelStatistics(m);
    // The default display is plain log power: the thresholded powers spread about 2–3x wider than
    // RADIATE's (docs/simulator.md, "Realism"). Pinned so that a change to it is a decision, not an accident.
    EXPECT_GT(m.excess_p90 / r.excess_p90, 1.8);
  }
  {
    SCOPED_TRACE("display_compression = 0.35 (the RADIATE match of docs/simulator.md)");
    sim::ScanningOptions o = radiate();
    o.display_compression = 0.35;
    const PowerStatistics m = simulate(o);
    expectPixelStatistics(m);
    EXPECT_NEAR(m.excess_p50 / r.excess_p50, 1.0, 0.4);
    EXPECT_NEAR(m.excess_p90 / r.excess_p90, 1.0, 0.4);
    EXPECT_NEAR(m.excess_p99 / r.excess_p99, 1.0, 0.4);
  }
}

TEST(RadarSim, AutomotiveDatarootReadsBack) {
  const std::string dir = freshTempDir("sim_auto");
  const sim::SimTrajectory ego = sim::builtinDrive(40.0);
  sim::WorldOptions wo;
  wo.seed = 11;
  sim::SequenceOptions seq;
  seq.start = 40;  // under way
  seq.frames = 40;
  sim::writeAutomotiveSequence(dir, ego, wo, sim::AutomotiveOptions(), seq);

  const NuScenesDataset data(dir);
  ASSERT_EQ(data.scenes().size(), 1u);
  EXPECT_EQ(data.scenes()[0].name, "sim-0001");
  ASSERT_EQ(data.radarChannels().size(), 5u);
  const auto sweeps = data.radarSweeps(data.scenes()[0]);
  std::map<std::string, std::vector<std::int64_t>> stamps;
  for (const auto& s : sweeps) stamps[s.channel].push_back(s.timestamp_us);
  ASSERT_EQ(stamps.size(), 5u);
  EXPECT_EQ(stamps["RADAR_FRONT"].size(), 40u);
  for (const auto& [channel, t] : stamps) {
    EXPECT_GE(t.size(), 38u) << channel;
    for (std::size_t k = 1; k < t.size(); ++k) EXPECT_NEAR((t[k] - t[k - 1]) * 1e-6, 1.0 / 13.0, 0.005) << channel;
  }
  EXPECT_NE(stamps["RADAR_FRONT"][3], stamps["RADAR_FRONT_LEFT"][3]);  // unsynchronised

  // Every sweep: ego pose = the trajectory at its time; stationary detections carry the Doppler
  // of the sensor's own motion.
  std::size_t points = 0;
  std::vector<double> residual;
  for (const auto& s : sweeps) {
    const double t = ego.stamps()[seq.start] + (s.timestamp_us - seq.start_stamp_us) * 1e-6;
    const Pose2 truth = ego.at(t);
    const Pose2 pose = toPose2(s.ego_to_global);
    EXPECT_NEAR(pose.x(), truth.x(), 1e-4);  // timestamps are whole µs
    EXPECT_NEAR(pose.y(), truth.y(), 1e-4);
    EXPECT_NEAR(normalizeAngle(pose.z() - truth.z()), 0.0, 1e-6);
    const auto cloud = readNuScenesRadarPcd(s.path, NuScenesRadarFilter(), 0);
    points += cloud.size();
    const Pose2 mount = toPose2(s.sensor_to_ego);
    const Eigen::Vector3d v = ego.velocity(t);
    const Eigen::Vector2d vs(v.x() - v.z() * mount.y(), v.y() + v.z() * mount.x());  // sensor velocity, vehicle axes
    const double c = std::cos(mount.z()), sn = std::sin(mount.z());
    const Eigen::Vector2d v_sensor(c * vs.x() + sn * vs.y(), -sn * vs.x() + c * vs.y());  // sensor axes
    for (const auto& p : cloud) {
      const double r = std::hypot(p.x, p.y);
      if (r < 1.0) continue;
      residual.push_back(std::abs(p.doppler + (v_sensor.x() * p.x + v_sensor.y() * p.y) / r));
    }
  }
  EXPECT_GT(points / sweeps.size(), 10u);
  EXPECT_LT(points / sweeps.size(), 126u);
  std::nth_element(residual.begin(), residual.begin() + residual.size() / 2, residual.end());
  EXPECT_LT(residual[residual.size() / 2], 0.2);  // most detections are stationary, σ = 0.1 m/s
  fs::remove_all(dir);
}

TEST(OxfordSequence, SimulatedSequenceRoundTrip) {
  // Simulate → read: every scan's metadata and the ground truth match what was written.
  const std::string dir = freshTempDir("oxford_seq");
  const sim::SimTrajectory ego = sim::builtinDrive(30.0);
  sim::WorldOptions world;
  world.seed = 7;
  sim::ScanningOptions scanning;
  sim::SequenceOptions seq;
  seq.start = 60;  // under way
  seq.frames = 4;
  const auto summary = sim::writeScanningSequence(dir, ego, world, scanning, seq);
  EXPECT_EQ(summary.frames, 4u);
  EXPECT_GT(summary.distance, 5.0);

  const auto stamps = readOxfordTimestamps(dir + "/radar.timestamps");
  ASSERT_EQ(stamps.size(), 4u);
  const auto rows = readOxfordRadarOdometry(dir + "/gt/radar_odometry.csv");
  ASSERT_EQ(rows.size(), 3u);
  const sim::World w = sim::World::generate(ego, world);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(stamps[k].stamp, seq.start_stamp_us + static_cast<std::int64_t>(250000 * k));
    const std::string path = dir + "/radar/" + std::to_string(stamps[k].stamp) + ".png";
    const PolarScan r = readOxfordPolarPng(path);
    EXPECT_EQ(r.stamp, stamps[k].stamp);
    EXPECT_EQ(r.stamp_us.front(), stamps[k].stamp);  // Oxford: the stamp marks the sweep's start
    EXPECT_EQ(r.stamp_us[200], stamps[k].stamp + 125000);
    EXPECT_EQ(r.encoder[100], 1400);
    EXPECT_NEAR(r.angle[100], -kPi / 2, 1e-12);
    // The pixels are what the renderer produced for that frame.
    PolarScan expected;
    sim::renderScan(w, ego, ego.stamps()[seq.start + k], world.seed, k, scanning, expected);
    EXPECT_EQ(r.power, expected.power) << path;
  }
  for (std::size_t k = 0; k < rows.size(); ++k) {
    // As in the dataset: the radar timestamps in their own columns, source_ and
    // destination_timestamp half a sweep later.
    EXPECT_EQ(rows[k].destination_radar, stamps[k].stamp);
    EXPECT_EQ(rows[k].source_radar, stamps[k + 1].stamp);
    EXPECT_EQ(rows[k].destination, stamps[k].stamp + 125000);
    EXPECT_EQ(rows[k].source, stamps[k + 1].stamp + 125000);
    // The later scan's pose in the earlier one's frame, in Oxford axes (y right, yaw clockwise).
    const Pose2 d = between(ego.at(ego.stamps()[seq.start + k]), ego.at(ego.stamps()[seq.start + k + 1]));
    EXPECT_NEAR(rows[k].x, d.x(), 1e-9);
    EXPECT_NEAR(rows[k].y, -d.y(), 1e-9);
    EXPECT_NEAR(rows[k].yaw, -d.z(), 1e-9);
    EXPECT_GT(rows[k].x, 0.5);  // driving forwards
  }
  fs::remove_all(dir);
}

// ---- the oxford profile: what it adds, each against what the real Oxford scans show ----------

namespace {
/// The oxford profile's sensor with no scatterers and no ghosts, in a world of given primitives.
sim::ScanningOptions oxfordBare() {
  sim::WorldOptions w;
  sim::ScanningOptions o;
  sim::applyProfile(sim::ScanningProfile::Oxford, w, o);
  o.scatterer_density = 0.0;
  o.ghost_probability = 0.0;
  return o;
}
}  // namespace

TEST(RadarSimOxford, CountsDisplayIsNavtechsStaircaseWithTheNoiseFloorOfTheRealScans) {
  // No world: noise alone. Navtech stores a count n as ⌊20·log10 n + 0.12⌋, so only 0, 6, 9, 12,
  // 14, 15, 17, 18, 19, 20, ... occur near the floor (as in the real files), and with a noise mean
  // of 2.45 counts the share of zeros (n < 2) is 1 − exp(−2 / 2.45) = 0.558.
  const sim::SimTrajectory ego = straight(1e-9);
  const sim::World w = sim::World::fromPrimitives(ego, {}, {});
  PolarScan s;
  sim::renderScan(w, ego, 0.0, 1, 0, oxfordBare(), s);
  std::map<int, std::size_t> hist;
  std::size_t n = 0;
  for (int a = 0; a < s.azimuths; ++a)
    for (int b = 0; b < s.bins; ++b)
      if (s.rangeOf(b) > 5.0) {
        ++hist[s.row(a)[b]];
        ++n;
      }
  for (int v : {1, 2, 3, 4, 5, 7, 8, 10, 11, 13, 16}) EXPECT_EQ(hist[v], 0u) << "value " << v << " cannot be stored";
  for (int v : {0, 6, 9, 12, 14, 15}) EXPECT_GT(hist[v], 0u) << v;
  EXPECT_NEAR(static_cast<double>(hist[0]) / n, 1.0 - std::exp(-2.0 / 2.45), 0.01);
}

TEST(RadarSimOxford, AzimuthAndRangeResponseOfAPoleFollowTheRealScans) {
  // A lone pole 20 m ahead. On the real scans a strong isolated return falls, in its neighbouring
  // azimuths (lower quartile over 2,456 returns), by about 8, 20, 29 and 38 dB at 0.9°, 1.8°, 2.7°
  // and 3.6°, and along its azimuth by about 31 dB at 0.9 m (docs/simulator.md). Bytes are 0.5 dB.
  const sim::SimTrajectory ego = straight(1e-9);
  const sim::World w = sim::World::fromPrimitives(ego, {}, {{{20.0, 0.0}, 0.12, sim::Material::Pole}});
  const sim::ScanningOptions o = oxfordBare();
  std::vector<std::vector<double>> fall(5), behind;
  for (int frame = 0; frame < 15; ++frame) {
    PolarScan s;
    sim::renderScan(w, ego, 0.0, 1, static_cast<std::uint64_t>(frame), o, s);
    auto peak = [&](int a, double lo, double hi) {
      int best = 0;
      for (int b = 0; b < s.bins; ++b)
        if (s.rangeOf(b) >= lo && s.rangeOf(b) <= hi)
          best = std::max<int>(best, s.row((a + s.azimuths) % s.azimuths)[b]);
      return best;
    };
    // The pole sits between azimuths 399 and 0 (0°, the first azimuth, is at 0.84° right).
    const int centre = peak(0, 19.7, 20.3) >= peak(399, 19.7, 20.3) ? 0 : 399;
    const int p0 = peak(centre, 19.7, 20.3);
    for (int k = 1; k <= 4; ++k) {
      const int side = centre == 0 ? k : -k;  // away from the other near azimuth
      fall[k].push_back(0.5 * (p0 - peak(centre + side, 19.7, 20.3)));
    }
    fall[0].push_back(0.5 * (p0 - peak(centre, 20.7, 21.0)));  // 0.9 m behind it
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  EXPECT_NEAR(median(fall[1]), 8.0, 5.0);
  EXPECT_NEAR(median(fall[2]), 20.0, 5.0);
  EXPECT_NEAR(median(fall[3]), 29.0, 5.0);
  EXPECT_NEAR(median(fall[4]), 38.0, 6.0);
  EXPECT_NEAR(median(fall[0]), 31.0, 7.0);
}

TEST(RadarSimOxford, ScatterersLieOffTheRoadAndBehindFacadesOnlyDimmed) {
  // An empty straight street (the ego at its start, 100 m of road ahead): along the road
  // (azimuth 0, forward) only noise and sidelobes, beside it (azimuth 100, to the right) the
  // scatterer field: far more bins above 0.2.
  const sim::SimTrajectory ego = straight(10.0);
  const sim::World w = sim::World::fromPrimitives(ego, {}, {});
  sim::ScanningOptions o = oxfordBare();
  o.scatterer_density = 0.16;
  PolarScan s;
  sim::renderScan(w, ego, 0.0, 1, 0, o, s);
  auto above = [&](int a0, int a1) {
    int n = 0, all = 0;
    for (int a = a0; a <= a1; ++a)
      for (int b = 0; b < s.bins; ++b)
        if (s.rangeOf(b) > 10 && s.rangeOf(b) < 60) {
          n += s.row((a + s.azimuths) % s.azimuths)[b] > 51;
          ++all;
        }
    return static_cast<double>(n) / all;
  };
  EXPECT_LT(above(-2, 2), 0.002) << "along the road";
  EXPECT_GT(above(90, 110), 0.02) << "beside it";
  // A facade 8 m to the right hides what is behind it, but only dimmed (over_occluder_db).
  const sim::World walled = sim::World::fromPrimitives(ego, {{{-100, -8}, {100, -8}, sim::Material::Building}}, {});
  PolarScan t;
  sim::renderScan(walled, ego, 0.0, 1, 0, o, t);
  int open = 0, hidden = 0;
  for (int a = 90; a <= 110; ++a)
    for (int b = 0; b < s.bins; ++b)
      if (s.rangeOf(b) > 20 && s.rangeOf(b) < 60) {
        open += s.row(a)[b] > 51;
        hidden += t.row(a)[b] > 51;
      }
  EXPECT_LT(hidden, open / 3);
  EXPECT_GT(hidden, 0);
}

TEST(RadarSimOxford, BackRowsComeFromTheirOwnRandomStream) {
  // Rows of buildings behind the street are added after it: the street is the same either way.
  const sim::SimTrajectory ego = straight(10.0);
  sim::WorldOptions a;
  a.seed = 9;
  sim::WorldOptions b = a;
  b.back_rows = 3;
  const sim::World wa = sim::World::generate(ego, a), wb = sim::World::generate(ego, b);
  ASSERT_GT(wb.segments().size(), wa.segments().size() + 20);
  for (std::size_t i = 0; i < wa.segments().size(); ++i) {
    EXPECT_EQ(wa.segments()[i].a, wb.segments()[i].a) << i;
    EXPECT_EQ(wa.segments()[i].b, wb.segments()[i].b) << i;
  }
  for (std::size_t i = wa.segments().size(); i < wb.segments().size(); ++i) {
    EXPECT_EQ(wb.segments()[i].material, sim::Material::Building);
    EXPECT_GT(std::abs(wb.segments()[i].a.y()), b.road_half_width_max + 7.0) << i;  // behind the street
  }
  EXPECT_EQ(wa.circles().size(), wb.circles().size());
  EXPECT_EQ(wa.movers().size(), wb.movers().size());
}

TEST(RadarSimOxford, ProfileReproducesTheRealOxfordScansOnADriveItWasNotCalibratedOn) {
  // The realism report's comparison (radar_sim --realism) on 8 scans of a drive and seed the profile
  // was not calibrated on, against the 11 real Oxford scans: most of the 25 fields within the
  // scanning issue's tolerances and a small error (docs/simulator.md gives every field); the
  // radiate profile, calibrated to RADIATE, fails almost all of them.
  const std::string real_dir = std::string(RADAR_NDT_SHARED_DATA) + "/oxford-radar-real";
  const std::string drive = std::string(RADAR_NDT_SHARED_DATA) + "/oxford-radar-gt/2019-01-16-13-42-28.txt";
  if (!fs::exists(real_dir) || !fs::exists(drive)) GTEST_SKIP() << "no " << real_dir << " (../shared/data is absent)";
  const PowerThreshold front;
  const ScanStatisticsOptions options;
  auto measure = [&](const PolarScan& s) { return scanStatistics(s, front, options); };
  std::vector<ScanStatistics> real;
  const ScanningSequence real_sequence(real_dir, ScanFormat::Oxford);
  for (std::size_t k = 0; k < real_sequence.size(); ++k) real.push_back(measure(real_sequence.load(k)));
  const ScanStatistics r = summarize(real).median;
  const sim::SimTrajectory ego(readTrajectory(drive), 0.25);
  auto fieldsWithin = [&](sim::ScanningProfile profile) -> RealismCheck {
    sim::WorldOptions wo;
    wo.seed = 2;
    sim::ScanningOptions so;
    sim::applyProfile(profile, wo, so);
    const sim::World w = sim::World::generate(ego, wo);
    std::vector<ScanStatistics> simulated;
    PolarScan s;
    const std::size_t stride = (ego.size() - 5000) / 8;  // spread over the rest of the drive, as radar_sim --realism
    for (std::size_t k = 0; k < 8; ++k) {
      sim::renderScan(w, ego, ego.stamps()[5000 + stride * k], wo.seed, k, so, s);
      simulated.push_back(measure(s));
    }
    const RealismCheck c = compareRealism(summarize(simulated).median, r, options);
    for (const auto& f : c.failures) std::printf("  %s: %s\n", sim::toString(profile), f.c_str());
    std::printf("%s: %zu of %zu fields within the tolerances, error %.1f\n", sim::toString(profile),
                c.fields - c.failures.size(), c.fields, c.error);
    return c;
  };
  const RealismCheck oxford = fieldsWithin(sim::ScanningProfile::Oxford);
  // 25 fields at the edge of their tolerances would give an error of 25; without the scatterer
  // field, the azimuth sidelobes or the returns from behind facades the error is 35 to 95.
  EXPECT_GE(oxford.fields - oxford.failures.size(), 20u);
  EXPECT_LT(oxford.error, 30.0);
  const RealismCheck radiate = fieldsWithin(sim::ScanningProfile::Radiate);
  EXPECT_LE(radiate.fields - radiate.failures.size(), 5u);
}

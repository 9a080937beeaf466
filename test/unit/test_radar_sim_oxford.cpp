// radar_sim's oxford profile: what it adds to the sensor model, each checked against what the real
// Oxford scans show, and its realism on a drive it was not calibrated on.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include <gtest/gtest.h>

#include "radar_ndt/frontend/power_threshold.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/io/oxford_ground_truth.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/io/radiate_scan.h"
#include "radar_ndt/io/scanning_sequence.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/sim/radar_sim.h"
#include "radar_ndt/sim/scan_statistics.h"
#include "sim_support.h"
#include "test_support.h"

using namespace radar_ndt;
using radar_ndt::sim::compareRealism;
using radar_ndt::sim::RealismCheck;
using radar_ndt::sim::ScanStatistics;
using radar_ndt::sim::scanStatistics;
using radar_ndt::sim::ScanStatisticsOptions;
using radar_ndt::sim::StatisticsSummary;
using radar_ndt::sim::summarize;
using radar_ndt::test::freshTempDir;
using radar_ndt::test::readBytes;
using namespace radar_ndt::test;
namespace fs = std::filesystem;

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
    for (const auto& f : c.failures) std::printf("  %s: %s\n", toString(profile), f.c_str());
    std::printf("%s: %zu of %zu fields within the tolerances, error %.1f\n", toString(profile),
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

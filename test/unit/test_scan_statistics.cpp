// Per-band statistics of polar scans and the realism comparison (radar_sim --realism).
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "radar_ndt/sim/scan_statistics.h"

using namespace radar_ndt;
using namespace radar_ndt::sim;

namespace {
/// 4 azimuths x 100 bins of 1 m (bin b at b + 0.5 m): power byte = `value(a, b)`.
template <typename F>
PolarScan scanOf(F value) {
  PolarScan s;
  s.azimuths = 4;
  s.bins = 100;
  s.range_resolution = 1.0;
  s.range_offset_bins = 0.5;
  s.power.resize(400);
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 100; ++b)
      s.power[static_cast<std::size_t>(a) * 100 + b] = static_cast<std::uint8_t>(value(a, b));
  s.angle.assign(4, 0.0);
  s.stamp_us.assign(4, 0);
  s.measured.assign(4, 1);
  return s;
}
}  // namespace

TEST(ScanStatistics, FractionsAndPercentilesPerBandCountEveryAzimuth) {
  // Band 2–15 m holds bins 2..14 (centres 2.5..14.5 m): 13 bins x 4 azimuths. Bin 10 of azimuth 0
  // is 200 and of azimuth 1 is 100; every other bin is b (its index).
  const PolarScan s = scanOf([](int a, int b) { return b == 10 && a == 0 ? 200 : b == 10 && a == 1 ? 100 : b; });
  ScanStatisticsOptions o;
  o.bands = {{2.0, 15.0}, {45.0, 62.5}};
  const ScanStatistics st = scanStatistics(s, o);
  ASSERT_EQ(st.bands.size(), 2u);
  const BandStatistics& near = st.bands[0];
  EXPECT_EQ(near.bins, 52u);
  // above 0.2 (byte > 51): the 200 and the 100; above 0.5 (> 127.5): the 200 only.
  EXPECT_DOUBLE_EQ(near.above[0], 2.0 / 52.0);
  EXPECT_DOUBLE_EQ(near.above[1], 2.0 / 52.0);
  EXPECT_DOUBLE_EQ(near.above[2], 1.0 / 52.0);
  // Nearest rank: p50 is the 26th smallest of 2,2,2,2,3,...: the values 2..14 four times over
  // (the two replaced 10s moved up): the 26th is 8; p99 is the 52nd (largest): 200.
  EXPECT_DOUBLE_EQ(near.percentile[0], 8.0 / 255.0);
  EXPECT_DOUBLE_EQ(near.percentile[2], 200.0 / 255.0);
  // 45–62.5 m: bins 45..61 (centres 45.5..61.5; 62.5 is outside [45, 62.5)): 17 bins.
  EXPECT_EQ(st.bands[1].bins, 68u);
  EXPECT_DOUBLE_EQ(st.bands[1].above[0], 10.0 / 17.0) << "bytes 52..61 of 45..61 are above 0.2";
}

TEST(ScanStatistics, SummaryIsTheMedianWithMinAndMax) {
  std::vector<ScanStatistics> v;
  for (int k : {3, 1, 2}) {
    ScanStatistics s;
    BandStatistics b;
    b.band = {2, 15};
    b.bins = 10;
    b.above = {0.1 * k};
    b.percentile = {k / 255.0};
    s.bands.push_back(b);
    s.points = static_cast<std::size_t>(1000 * k);
    v.push_back(s);
  }
  const StatisticsSummary m = summarize(v);
  EXPECT_EQ(m.scans, 3u);
  EXPECT_NEAR(m.median.bands[0].above[0], 0.2, 1e-12);
  EXPECT_NEAR(m.min.bands[0].above[0], 0.1, 1e-12);
  EXPECT_NEAR(m.max.bands[0].above[0], 0.3, 1e-12);
  EXPECT_EQ(m.median.points, 2000u);
  EXPECT_THROW(summarize({}), std::invalid_argument);
  v[1].bands.push_back(v[1].bands[0]);
  EXPECT_THROW(summarize(v), std::invalid_argument);
}

TEST(ScanStatistics, RealismToleranceIsRelativeForFractionsAndAbsoluteForPercentiles) {
  ScanStatisticsOptions o;
  o.bands = {{2, 15}};
  o.levels = {0.333};
  o.percentiles = {50};
  auto make = [](double above, double p50, std::size_t points) {
    ScanStatistics s;
    BandStatistics b;
    b.band = {2, 15};
    b.above = {above};
    b.percentile = {p50};
    s.bands.push_back(b);
    s.points = points;
    return s;
  };
  const ScanStatistics real = make(0.020, 9.0 / 255, 6000);
  EXPECT_TRUE(compareRealism(make(0.024, 12.0 / 255, 7400), real, o).passed());   // +20 %, +3, +23 %
  EXPECT_FALSE(compareRealism(make(0.026, 9.0 / 255, 6000), real, o).passed());   // +30 %
  EXPECT_FALSE(compareRealism(make(0.020, 13.0 / 255, 6000), real, o).passed());  // +4/255
  EXPECT_FALSE(compareRealism(make(0.020, 9.0 / 255, 4400), real, o).passed());   // −27 % points
  // A small fraction: ±0.002 absolute is the larger tolerance.
  EXPECT_TRUE(compareRealism(make(0.0025, 9.0 / 255, 6000), make(0.001, 9.0 / 255, 6000), o).passed());
  const RealismCheck c = compareRealism(make(0.026, 13.0 / 255, 6000), real, o);
  EXPECT_EQ(c.fields, 3u);
  EXPECT_EQ(c.failures.size(), 2u);
  EXPECT_EQ(c.within, (std::vector<bool>{false, false, true}));  // the fraction, p50, the points
}

TEST(ScanStatistics, RejectsBadOptionsAndScans) {
  ScanStatisticsOptions o;
  o.bands = {{15, 2}};
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = {};
  o.levels = {1.5};
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = {};
  o.percentiles = {0};
  EXPECT_THROW(o.validate(), std::invalid_argument);
  PolarScan empty;
  EXPECT_THROW(scanStatistics(empty), std::invalid_argument);
}

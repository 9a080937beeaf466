// The up/down-chirp correction: shifts made by the simulator's chirp model (the same displacement
// s·g(θ) the correction assumes, applied per azimuth) are found from the scan alone and undone;
// scans without chirp types are left alone.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "radar_ndt/frontend/chirp_correction.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;

namespace {

// 400 azimuths of 2000 bins (0.0438 m), noise, and walls: returns at ranges that vary slowly with
// the bearing (so neighbouring azimuths see the same scenery), plus point scatterers.
PolarScan sceneScan(std::uint32_t seed) {
  PolarScan s;
  s.azimuths = 400;
  s.bins = 2000;
  s.range_resolution = 0.0438;
  s.range_offset_bins = 0.5;
  s.power.resize(static_cast<std::size_t>(s.azimuths) * s.bins);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(0, 40);
  for (int a = 0; a < s.azimuths; ++a) {
    s.angle.push_back(std::remainder(-2.0 * kPi * a / s.azimuths, 2.0 * kPi));
    s.stamp_us.push_back(625 * a);
    s.chirp_up.push_back(a % 2);
    for (int b = 0; b < s.bins; ++b) s.row(a)[b] = static_cast<std::uint8_t>(noise(rng));
    const double theta = s.angle[a];
    for (double r : {12.0 + 3.0 * std::cos(theta), 27.0 + 5.0 * std::sin(2 * theta), 41.0 + 2.0 * std::cos(3 * theta),
                     55.0 + 4.0 * std::sin(theta)}) {
      const double c = r / s.range_resolution - s.range_offset_bins;
      for (int b = static_cast<int>(c) - 6; b <= static_cast<int>(c) + 6; ++b)
        s.row(a)[b] = static_cast<std::uint8_t>(
            std::max<double>(s.row(a)[b], 220.0 * std::exp(-0.5 * std::pow((b - c) / 1.5, 2))));
    }
  }
  return s;
}

// The chirp shifts of a radar moving at `v` (m/s, vehicle frame) with coupling `beta`.
void chirpShift(PolarScan& s, const Eigen::Vector2d& v, double beta) {
  shiftRanges(s, [&](int a) {
    const double radial = -(v.x() * std::cos(s.angle[a]) + v.y() * std::sin(s.angle[a]));
    return (s.chirp_up[a] ? 1.0 : -1.0) * beta * radial;
  });
}

double meanAbsDifference(const PolarScan& a, const PolarScan& b, double max_range) {
  double sum = 0;
  std::size_t n = 0;
  for (int az = 0; az < a.azimuths; ++az)
    for (int bin = 0; a.rangeOf(bin) < max_range; ++bin) {
      sum += std::abs(static_cast<int>(a.row(az)[bin]) - static_cast<int>(b.row(az)[bin]));
      ++n;
    }
  return sum / static_cast<double>(n);
}

}  // namespace

TEST(ChirpCorrection, FindsTheShiftsOfAMovingRadarAndUndoesThem) {
  for (const Eigen::Vector2d& v :
       {Eigen::Vector2d(25.0, 0.0), Eigen::Vector2d(-8.0, 3.0), Eigen::Vector2d(12.0, -6.0)}) {
    const PolarScan clean = sceneScan(7);
    PolarScan s = clean;
    const double beta = 0.049;
    chirpShift(s, v, beta);
    const ChirpShiftEstimate e = estimateChirpShift(s);
    ASSERT_TRUE(e.valid) << v.transpose();
    EXPECT_NEAR(e.u.x(), beta * v.x(), 0.03) << v.transpose();  // u = β·v
    EXPECT_NEAR(e.u.y(), beta * v.y(), 0.03) << v.transpose();
    EXPECT_GT(e.pairs, 150);
    const double before = meanAbsDifference(s, clean, 60.0);
    correctChirpShift(s, e.u);
    const double after = meanAbsDifference(s, clean, 60.0);
    EXPECT_LT(after, 0.5 * before) << v.transpose() << ": " << before << " -> " << after;
  }
}

TEST(ChirpCorrection, AStandingRadarAndScansWithoutChirpTypesAreLeftAlone) {
  PolarScan s = sceneScan(3);
  const ChirpShiftEstimate still = estimateChirpShift(s);
  ASSERT_TRUE(still.valid);
  EXPECT_LT(still.u.norm(), 0.01);
  PolarScan plain = sceneScan(3);
  plain.chirp_up.clear();
  const PolarScan copy = plain;
  EXPECT_FALSE(correctChirps(plain).valid);
  EXPECT_EQ(plain.power, copy.power);
  ChirpCorrectionOptions off;
  off.enabled = false;
  chirpShift(s, Eigen::Vector2d(20.0, 0.0), 0.049);
  const PolarScan shifted = s;
  EXPECT_FALSE(correctChirps(s, off).valid);
  EXPECT_EQ(s.power, shifted.power);
}

TEST(ChirpCorrection, ShiftRangesMovesRowsBySubBinAmounts) {
  PolarScan s;
  s.azimuths = 2;
  s.bins = 20;
  s.range_resolution = 0.1;
  s.power.assign(40, 0);
  s.row(0)[10] = 200;
  s.row(1)[10] = 200;
  shiftRanges(s, [](int a) { return a == 0 ? 0.3 : -0.25; });  // 3 bins out; 2.5 bins in
  EXPECT_EQ(s.row(0)[13], 200);
  EXPECT_EQ(s.row(0)[10], 0);
  EXPECT_EQ(s.row(1)[7], 100);  // half between bins 7 and 8
  EXPECT_EQ(s.row(1)[8], 100);
}

TEST(ChirpCorrection, OptionsAreValidated) {
  ChirpCorrectionOptions o;
  o.max_range = o.min_range;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = ChirpCorrectionOptions{};
  o.top_share = 0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

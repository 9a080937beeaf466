// Power thresholding front-end: constructed scans (positions, power, covariance orientation, time
// offsets) and the real RADIATE scans (point counts, power range).
#include <atomic>
#include <cmath>
#include <filesystem>
#include <thread>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "radar_ndt/frontend/power_threshold.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/io/radiate_scan.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;

namespace {

/// An Oxford-like scan of noise at `floor` with one bright cell per (azimuth, bin) in `spots`.
PolarScan constructedScan(std::uint8_t floor, const std::vector<std::pair<int, int>>& spots, std::uint8_t value = 230) {
  PolarScan s;
  s.azimuths = 400;
  s.bins = 1600;
  s.range_resolution = 0.0438;
  s.range_offset_bins = 0.5;
  s.power.assign(static_cast<std::size_t>(s.azimuths) * s.bins, floor);
  const PolarConvention c = OxfordPolarOptions().convention;
  for (int a = 0; a < s.azimuths; ++a) {
    s.angle.push_back(c.toVehicleAngle(2 * kPi * a / s.azimuths));
    s.stamp_us.push_back(1000000 + a * 625);
  }
  s.measured.assign(s.azimuths, 1);
  s.stamp = 1000000;
  for (const auto& [a, b] : spots)
    for (int db = -1; db <= 1; ++db) s.power[static_cast<std::size_t>(a) * s.bins + b + db] = value;
  return s;
}

}  // namespace

TEST(PowerThreshold, PolarPathPutsEachCellAtItsRangeAndAngle) {
  PowerThresholdOptions o;
  o.cartesian = false;
  const PowerThreshold front(o);
  const int a = 50, b = 700;  // 45° clockwise of the front = front-right, at ~30.7 m
  const PolarScan s = constructedScan(20, {{a, b}});
  pcl::PointCloud<PointRadar> cloud;
  front.compute(s, cloud);
  ASSERT_EQ(cloud.size(), 3u);  // the three bright bins
  const PointRadar& p = cloud[1];
  const double r = s.rangeOf(b);
  EXPECT_NEAR(std::hypot(p.x, p.y), r, 1e-3);
  EXPECT_NEAR(std::atan2(p.y, p.x), -kPi / 4, 1e-6);
  EXPECT_LT(p.y, 0.f);  // right side: −y
  EXPECT_EQ(p.z, 0.f);
  EXPECT_NEAR(p.power, 230.0 / 255.0, 1e-6);
  EXPECT_NEAR(p.time_offset, a * 625e-6, 1e-9);
  // Covariance: tight along the beam (range resolution), wide across it (beam width at 30 m).
  Eigen::Matrix2d cov;
  cov << p.cov_xx, p.cov_xy, p.cov_xy, p.cov_yy;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
  const Eigen::Vector2d radial(std::cos(-kPi / 4), std::sin(-kPi / 4));
  EXPECT_GT(std::abs(es.eigenvectors().col(0).dot(radial)), 0.999);  // smallest axis along the beam
  EXPECT_NEAR(std::sqrt(es.eigenvalues()(0)), 0.0438, 0.01);
  EXPECT_NEAR(std::sqrt(es.eigenvalues()(1)), r * (2.0 * kPi / 180.0) / 2.355, 0.02);
}

TEST(PowerThreshold, CartesianPathThresholdsTheResampledImage) {
  const PowerThreshold front;  // paper defaults
  EXPECT_DOUBLE_EQ(front.options().cartesian_resolution, 0.125);
  EXPECT_DOUBLE_EQ(front.options().max_range, 62.5);
  EXPECT_FLOAT_EQ(front.options().threshold, 0.333f);
  const PolarScan s = constructedScan(20, {{0, 500}, {100, 900}, {300, 1500}});  // 1500 bins = 65.7 m: beyond the limit
  pcl::PointCloud<PointRadar> cloud;
  front.compute(s, cloud);
  ASSERT_FALSE(cloud.empty());
  int front_spot = 0, right_spot = 0;
  for (const auto& p : cloud) {
    EXPECT_GE(p.power, 0.333f);
    EXPECT_LE(p.power, 1.0f);
    const double r = std::hypot(p.x, p.y);
    EXPECT_LE(r, 62.5 + 0.2);
    EXPECT_GE(r, 2.0 - 0.2);
    if (std::abs(p.x - s.rangeOf(500)) < 0.5 && std::abs(p.y) < 0.5) ++front_spot;
    if (std::abs(p.y + s.rangeOf(900)) < 0.5 && std::abs(p.x) < 0.6) ++right_spot;
    // Covariance positive definite and at least a pixel's worth.
    EXPECT_GT(p.cov_xx, 0.125 * 0.125 / 12 * 0.99);
    EXPECT_GT(p.cov_xx * p.cov_yy - p.cov_xy * p.cov_xy, 0.f);
  }
  EXPECT_GT(front_spot, 0);
  EXPECT_GT(right_spot, 0);
  EXPECT_EQ(front_spot + right_spot, static_cast<int>(cloud.size()));  // nothing from the noise floor or beyond 62.5 m
  // Right-side points were taken a quarter sweep after the front ones.
  for (const auto& p : cloud) {
    if (p.y < -10) {
      EXPECT_NEAR(p.time_offset, 0.0625, 0.003);
    }
  }
}

TEST(PowerThreshold, ThresholdAndRangeAreSettings) {
  const PolarScan s = constructedScan(100, {});  // 100/255 = 0.39: above the default threshold everywhere
  PowerThresholdOptions o;
  o.cartesian = false;
  pcl::PointCloud<PointRadar> all, none, near;
  PowerThreshold(o).compute(s, all);
  o.threshold = 0.5f;
  PowerThreshold(o).compute(s, none);
  EXPECT_TRUE(none.empty());
  o.threshold = 0.333f;
  o.max_range = 10.0;
  PowerThreshold(o).compute(s, near);
  EXPECT_GT(all.size(), 10 * near.size() / 2);
  for (const auto& p : near) EXPECT_LE(std::hypot(p.x, p.y), 10.0 + 1e-3);
  // Bins from min_range to max_range on each azimuth.
  const std::size_t per_azimuth = near.size() / 400;
  EXPECT_NEAR(static_cast<double>(per_azimuth), (10.0 - 2.0) / 0.0438, 2.0);
}

TEST(PowerThreshold, RealRadiateScans) {
  const std::string dir = std::string(RADAR_NDT_SHARED_DATA) + "/radiate-tiny-foggy/Navtech_Polar";
  if (!std::filesystem::exists(dir))
    GTEST_SKIP() << "no " << dir << " (../shared/data is absent): skipping the real-data check";
  const PowerThreshold cartesian;
  PowerThresholdOptions po;
  po.cartesian = false;
  const PowerThreshold polar(po);
  for (const char* name : {"000001.png", "000009.png", "000018.png"}) {
    const PolarScan s = readRadiatePolarPng(dir + "/" + name);
    pcl::PointCloud<PointRadar> c, p;
    cartesian.compute(s, c);
    polar.compute(s, p);
    // Measured on these scans: ~13–22k Cartesian points, ~3–4.5k polar ones (docs/results/scanning.md).
    EXPECT_GT(c.size(), 5000u) << name;
    EXPECT_LT(c.size(), 60000u) << name;
    EXPECT_GT(p.size(), 1000u) << name;
    EXPECT_LT(p.size(), c.size()) << name;
    for (const auto& pt : c) {
      ASSERT_GE(pt.power, 0.333f);
      ASSERT_LE(pt.power, 1.0f);
      ASSERT_LE(std::hypot(pt.x, pt.y), 62.5 + 0.1);
    }
    const PowerStatistics st = powerStatistics(cartesian.cartesianImage(s), 0.333f);
    EXPECT_EQ(st.points, c.size());
    EXPECT_GT(st.fraction_above, 0.005);
    EXPECT_LT(st.fraction_above, 0.1);
    EXPECT_LT(st.p50, st.p90);
    EXPECT_LT(st.p90, st.p99);
  }
}

TEST(PowerThreshold, ThreadsShareOneInstanceAndItsGeometry) {
  // The pipelines' workers call compute on one instance at once, on scans of two layouts in turn
  // (each change rebuilds the cached geometry under the others): every cloud is the one a fresh
  // instance gives.
  PolarScan fine = constructedScan(20, {{10, 300}, {200, 900}});
  PolarScan coarse = fine;
  coarse.range_resolution = 0.0596;  // another layout: the cache is rebuilt whenever it alternates
  std::vector<std::size_t> reference;
  for (const PolarScan* s : {&fine, &coarse}) {
    pcl::PointCloud<PointRadar> cloud;
    PowerThreshold(PowerThresholdOptions()).compute(*s, cloud);
    reference.push_back(cloud.size());
    ASSERT_GT(cloud.size(), 0u);
  }
  ASSERT_NE(reference[0], reference[1]);
  const PowerThreshold shared{PowerThresholdOptions()};
  std::atomic<int> wrong{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int i = 0; i < 12; ++i) {
        const int which = (t + i) % 2;
        pcl::PointCloud<PointRadar> cloud;
        shared.compute(which ? coarse : fine, cloud);
        wrong += cloud.size() != reference[static_cast<std::size_t>(which)];
      }
    });
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(wrong.load(), 0);
}

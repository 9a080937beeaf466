// ProbabilisticSubmap: the sliding window, motion of old cycles, and covariance growth against a
// hand-computed case.
#include <gtest/gtest.h>

#include <cmath>

#include "radar_ndt/frontend/probabilistic_submap.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;

namespace {
pcl::PointCloud<PointRadar> onePoint(float x, float y, float cov) {
  pcl::PointCloud<PointRadar> c;
  PointRadar p(x, y, 0.f);
  p.cov_xx = p.cov_yy = cov;
  c.push_back(p);
  return c;
}
}  // namespace

TEST(ProbabilisticSubmap, SlidingWindowOfNCycles) {
  ProbabilisticSubmap map(3);
  const Eigen::Vector3d v(10.0, 0.0, 0.0);
  const Eigen::Matrix3d cov = Eigen::Matrix3d::Identity() * 1e-4;
  for (int k = 0; k < 5; ++k) map.add(onePoint(20.f, 0.f, 0.01f), v, cov, 0.1);
  EXPECT_EQ(map.cycles(), 3u);
  const auto c = map.cloud();
  ASSERT_EQ(c->size(), 3u);
  // Oldest first: the car drove 1 m a cycle, so the same landmark seen 2 cycles ago sits 2 m closer now.
  EXPECT_NEAR((*c)[0].x, 18.f, 1e-4);
  EXPECT_NEAR((*c)[1].x, 19.f, 1e-4);
  EXPECT_NEAR((*c)[2].x, 20.f, 1e-4);
  map.setSize(1);
  EXPECT_EQ(map.cloud()->size(), 1u);
}

TEST(ProbabilisticSubmap, CovarianceGrowsThroughTheMotionJacobian) {
  ProbabilisticSubmap map(2);
  // Velocity covariance: σ_vx = 0.1 m/s, σ_vy = 0.2 m/s, σ_ω = 0.01 rad/s; straight motion, dt = 0.5 s.
  Eigen::Matrix3d Sv = Eigen::Vector3d(0.01, 0.04, 1e-4).asDiagonal();
  const Eigen::Vector3d v(4.0, 0.0, 0.0);
  map.add(onePoint(10.f, 0.f, 0.0f), v, Sv, 0.0);
  map.add(pcl::PointCloud<PointRadar>(), v, Sv, 0.5);
  // Trapezoid: v̄ = v, Σ_v̄ = (Sv + Sv)/4 = Sv/2; motion (2, 0, 0), Σ_m = Σ_v̄ dt² (θ = 0: J = I).
  const Eigen::Matrix3d Sm = 0.5 * Sv * 0.25;
  EXPECT_TRUE(map.lastMotionCovariance().isApprox(Sm, 1e-12));
  const auto c = map.cloud();
  ASSERT_EQ(c->size(), 1u);
  const PointRadar& p = (*c)[0];
  EXPECT_NEAR(p.x, 8.f, 1e-5);
  // p' = p − t for θ = 0, so ∂p'/∂t = −I and ∂p'/∂θ = (p'_y, −p'_x) = (0, −8):
  // Σ' = Σ_m[xy] + [0; −8] σ_θ² [0, −8].
  EXPECT_NEAR(p.cov_xx, Sm(0, 0), 1e-9);
  EXPECT_NEAR(p.cov_yy, Sm(1, 1) + 64.0 * Sm(2, 2), 1e-8);
  EXPECT_NEAR(p.cov_xy, 0.0, 1e-9);
  // A third cycle grows it again: older points are trusted less.
  map.setSize(3);
  map.add(pcl::PointCloud<PointRadar>(), v, Sv, 0.5);
  EXPECT_GT((*map.cloud())[0].cov_yy, p.cov_yy);
}

TEST(ProbabilisticSubmap, TransformWithUncertaintyMatchesNumericJacobian) {
  pcl::PointCloud<PointRadar> c = onePoint(12.f, -5.f, 0.0f);
  const Pose2 m(1.0, 0.4, 0.1);
  const Eigen::Matrix3d Sm = Eigen::Vector3d(0.01, 0.02, 0.003).asDiagonal();
  transformWithUncertainty(c, m, Sm);
  // Numeric Jacobian of p' = R(−θ)(p − t).
  auto f = [](const Pose2& q) {
    const Pose2 local = compose(inverse(q), Pose2(12.0, -5.0, 0.0));
    return Eigen::Vector2d(local.x(), local.y());
  };
  Eigen::Matrix<double, 2, 3> J;
  for (int i = 0; i < 3; ++i) {
    Pose2 a = m, b = m;
    a[i] += 1e-6;
    b[i] -= 1e-6;
    J.col(i) = (f(a) - f(b)) / 2e-6;
  }
  const Eigen::Matrix2d S = J * Sm * J.transpose();
  EXPECT_NEAR(c[0].cov_xx, S(0, 0), 1e-5);
  EXPECT_NEAR(c[0].cov_xy, S(0, 1), 1e-5);
  EXPECT_NEAR(c[0].cov_yy, S(1, 1), 1e-5);
  EXPECT_NEAR(c[0].x, f(m).x(), 1e-5);
}

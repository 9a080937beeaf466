#pragma once
// Helpers shared by the matcher's tests: synthetic scan pairs, the matcher run on a pair, a point
// with a covariance, and a pose comparison.
#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "radar_ndt/point_types.h"
#include "radar_ndt/registration/weighted_ndt_2d.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/sim/synthetic_scan.h"

namespace radar_ndt {
namespace test {

constexpr double kDeg = kPi / 180.0;

/// A PointRadar cloud as another point type (intensity = power for PointXYZI).
template <typename PointT>
typename pcl::PointCloud<PointT>::Ptr convert(const pcl::PointCloud<PointRadar>& in) {
  typename pcl::PointCloud<PointT>::Ptr out(new pcl::PointCloud<PointT>);
  for (const auto& p : in) {
    PointT q;
    q.x = p.x;
    q.y = p.y;
    q.z = p.z;
    if constexpr (std::is_same_v<PointT, pcl::PointXYZI>) q.intensity = p.power;
    if constexpr (std::is_same_v<PointT, PointRadar>) q = p;
    out->push_back(q);
  }
  return out;
}

struct AlignResult {
  Pose2 pose;
  bool converged;
};

/// Matches `pair` with `ndt` from `guess`.
template <typename PointT>
AlignResult alignPair(const SyntheticScanPair& pair, const Pose2& guess, WeightedNDT2D<PointT, PointT>& ndt) {
  auto src = convert<PointT>(pair.source);
  auto tgt = convert<PointT>(pair.target);
  ndt.setInputSource(src);
  ndt.setInputTarget(tgt);
  pcl::PointCloud<PointT> out;
  ndt.align(out, toMatrix4<float>(guess));
  return {toPose2(ndt.getFinalTransformation()), ndt.hasConverged()};
}

inline void expectClose(const Pose2& est, const Pose2& truth, double tol_m, double tol_deg) {
  EXPECT_LT((est.head<2>() - truth.head<2>()).norm(), tol_m)
      << "est " << est.transpose() << " truth " << truth.transpose();
  EXPECT_LT(std::abs(normalizeAngle(est.z() - truth.z())) / kDeg, tol_deg)
      << "est " << est.transpose() << " truth " << truth.transpose();
}

/// 6000 points, up to 1 m and 2° apart.
inline SyntheticScanPair standardPair(std::uint32_t seed = 5) {
  SyntheticScanOptions o;
  o.points = 6000;
  o.seed = seed;
  o.max_translation = 1.0;
  o.max_rotation_deg = 2.0;
  return makeSyntheticScanPair(o);
}

/// A pair with 5 cm of position noise on every point (default motion range).
inline SyntheticScanPair noisyPair(std::uint32_t seed, std::size_t points) {
  SyntheticScanOptions o;
  o.points = points;
  o.seed = seed;
  o.noise_std = 0.05;
  return makeSyntheticScanPair(o);
}

/// The analytic gradient and Hessian `cost` gives at `x` against central differences of its value
/// (step 1e-6): the gradient within 1e-4 of its norm (+1e-6), the Hessian within 1e-3 of its norm.
template <typename Cost>
void expectDerivativesMatchFiniteDifferences(const Cost& cost, const Eigen::Vector3d& x, const std::string& what = "") {
  Eigen::Vector3d g;
  Eigen::Matrix3d H;
  cost(x, &g, &H);
  const double h = 1e-6;
  Eigen::Vector3d g_fd;
  Eigen::Matrix3d H_fd;
  for (int i = 0; i < 3; ++i) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d(i) = h;
    Eigen::Vector3d gp = Eigen::Vector3d::Zero(), gm = Eigen::Vector3d::Zero();
    Eigen::Matrix3d Hp;
    g_fd(i) = (cost(x + d, &gp, &Hp) - cost(x - d, &gm, &Hp)) / (2 * h);
    H_fd.col(i) = (gp - gm) / (2 * h);
  }
  EXPECT_LT((g - g_fd).norm(), 1e-4 * g.norm() + 1e-6) << what << "\n" << g.transpose() << "\n" << g_fd.transpose();
  EXPECT_LT((H - H_fd).norm(), 1e-3 * H.norm()) << what << "\n" << H << "\n" << H_fd;
}

inline PointRadar pointWith(float x, float y, float power, float cxx, float cxy, float cyy) {
  PointRadar p(x, y, 0.f, power);
  p.cov_xx = cxx;
  p.cov_xy = cxy;
  p.cov_yy = cyy;
  return p;
}

}  // namespace test
}  // namespace radar_ndt

// detail/sweep_cost.h and WeightedNDT2D::setSourceSweep: the source sweep's motion inside the match.
// The placement against SE(2)'s exact constant-velocity motion, the analytic gradient and Hessian
// against finite differences, the rigid cost when every point is at the reference time, and the
// matcher recovering a motion from a sweep skewed by it where a rigid match cannot.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "radar_ndt/registration/detail/ndt_cost.h"
#include "radar_ndt/registration/detail/ndt_grid.h"
#include "radar_ndt/registration/detail/source_points.h"
#include "radar_ndt/registration/detail/sweep_cost.h"
#include "registration_support.h"

using namespace radar_ndt;
using radar_ndt::test::expectClose;
using radar_ndt::test::kDeg;
using radar_ndt::test::noisyPair;

namespace {

constexpr double kSweep = 0.25;  // s, a Navtech sweep, and the step between scans

/// A point's time offset in a sweep starting at azimuth −π of the sensor at `pose` (seen there).
double sweepTime(const Pose2& pose, double wx, double wy) {
  const Pose2 local = between(pose, Pose2(wx, wy, 0));
  return kSweep * (std::atan2(local.y(), local.x()) + kPi) / (2 * kPi);
}

/// The source of `pair` re-seen by a sensor moving at body velocity `v` through its sweep: the
/// source's reference pose is `previous` ⊕ exp(v Δt), and each point (in the target's frame) is
/// seen from that pose ⊕ exp(v τ) at its time offset τ, which it carries.
pcl::PointCloud<PointRadar> skewedSource(const SyntheticScanPair& pair, const Pose2& previous, const Eigen::Vector3d& v,
                                         Pose2* source_pose) {
  const Pose2 x = compose(previous, integrateVelocity(v, kSweep));
  *source_pose = x;
  pcl::PointCloud<PointRadar> out;
  for (const auto& p : pair.source) {
    const Pose2 world = compose(pair.source_in_target, Pose2(p.x, p.y, 0));
    const double tau = sweepTime(x, world.x(), world.y());
    const Pose2 seen = between(compose(x, integrateVelocity(v, tau)), world);
    PointRadar q = p;
    q.x = static_cast<float>(seen.x());
    q.y = static_cast<float>(seen.y());
    q.time_offset = static_cast<float>(tau);
    out.push_back(q);
  }
  return out;
}

struct Problem {
  detail::NdtGrid grid;
  std::vector<detail::WeightedPoint2D> source;
};

Problem problemOf(const pcl::PointCloud<PointRadar>& target, const pcl::PointCloud<PointRadar>& source) {
  Problem p;
  detail::buildNdtGrid(target, 3.0, WeightedNDT2DSettings{}, p.grid);
  pcl::Indices all(source.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<pcl::index_t>(i);
  detail::weightSourcePoints(source, all, 0.0, p.source);
  return p;
}

}  // namespace

// q = x ⊕ m^α ⊕ p against SE(2)'s exact constant-velocity pose at the point's time: the same but for
// the sinc ratio left out, under a millimetre at a 8° sweep and 3 m of motion; the rotation exact.
TEST(SweepCost, PlacementIsTheConstantVelocityPoseAtThePointsTime) {
  const Pose2 previous(4.0, -2.0, 0.3);
  for (const Eigen::Vector3d& v : {Eigen::Vector3d(12.0, 0.5, 0.56), Eigen::Vector3d(-3.0, 1.0, -0.3)}) {
    const Pose2 x = compose(previous, integrateVelocity(v, kSweep));
    const double c = std::cos(x.z()), s = std::sin(x.z());
    const double phi = x.z() - previous.z();
    for (const double tau : {-0.125, -0.05, 0.0, 0.05, 0.125, 0.2, 0.25}) {  // < 0: before a mid-sweep reference
      const Pose2 truth = compose(compose(x, integrateVelocity(v, tau)), Pose2(20.0, -7.0, 0));
      const detail::SweepPlacement q = detail::placeInSweep(20.0, -7.0, tau / kSweep, c, s, x.x(), x.y(), phi,
                                                            x.x() - previous.x(), x.y() - previous.y());
      EXPECT_NEAR(q.qx, truth.x(), 1e-3) << "tau " << tau << " v " << v.transpose();
      EXPECT_NEAR(q.qy, truth.y(), 1e-3) << "tau " << tau << " v " << v.transpose();
    }
  }
  double cs, sn;
  for (const double a : {0.0, 0.1, -0.45, 0.5, 0.9, -2.0}) {
    detail::smallRotation(a, cs, sn);
    EXPECT_NEAR(cs, std::cos(a), 1e-9) << a;
    EXPECT_NEAR(sn, std::sin(a), 1e-9) << a;
  }
}

// The analytic gradient and Hessian agree with central differences of the value, away from the
// previous pose and with every point at its own time in the sweep.
TEST(SweepCost, DerivativesMatchFiniteDifferences) {
  const auto pair = noisyPair(5, 3000);
  const detail::SweepStep step{kSweep, Eigen::Vector3d(-2.5, 0.4, -0.05)};
  Pose2 x_true;
  const auto source = skewedSource(pair, step.previous, Eigen::Vector3d(10.0, 0.3, 0.4), &x_true);
  const Problem p = problemOf(pair.target, source);
  auto cost = [&](const Eigen::Vector3d& x, Eigen::Vector3d* g, Eigen::Matrix3d* H) {
    return detail::ndtSweepCost(p.grid, p.source, step, x, g, H);
  };
  for (const Eigen::Vector3d& x : {Eigen::Vector3d(x_true + Eigen::Vector3d(0.3, -0.2, 0.02)), x_true})
    radar_ndt::test::expectDerivativesMatchFiniteDifferences(cost, x);
}

// Points at the sweep's reference time (α = 0) are placed by x alone: the rigid cost, its
// derivatives and information, whatever the step.
TEST(SweepCost, PointsAtTheReferenceTimeGiveTheRigidCost) {
  const auto pair = noisyPair(7, 2000);
  Problem p = problemOf(pair.target, pair.source);
  for (auto& q : p.source) q.t = 0;
  const detail::SweepStep step{kSweep, Eigen::Vector3d(1.0, 2.0, 0.1)};
  const Eigen::Vector3d x(0.4, -0.3, 0.03);
  Eigen::Vector3d g0, g1;
  Eigen::Matrix3d H0, H1, I0, I1;
  std::size_t m0 = 0, m1 = 0;
  const double v0 = detail::ndtCost(p.grid, p.source, x, &g0, &H0, &m0, &I0);
  const double v1 = detail::ndtSweepCost(p.grid, p.source, step, x, &g1, &H1, &m1, &I1);
  EXPECT_NEAR(v1, v0, 1e-9 * std::abs(v0));
  EXPECT_LT((g1 - g0).norm(), 1e-9 * g0.norm());
  EXPECT_LT((H1 - H0).norm(), 1e-9 * H0.norm());
  EXPECT_LT((I1 - I0).norm(), 1e-9 * I0.norm());
  EXPECT_EQ(m1, m0);
}

// A sweep skewed by 3 m and 8° of motion: with its time offsets the matcher recovers the motion to
// centimetres, from the previous pose as its guess; a rigid match of the same points cannot (the
// points are a quarter sweep's motion apart on average). The aligned output is the de-skewed source.
TEST(SweepCost, MatcherRecoversTheMotionOfASkewedSweep) {
  const auto pair = noisyPair(11, 6000);
  const Pose2 previous(-1.0, 0.5, -0.1);
  const Eigen::Vector3d v(12.0, 0.2, 0.56);
  Pose2 x_true;
  const auto source = skewedSource(pair, previous, v, &x_true);
  auto src = pcl::make_shared<pcl::PointCloud<PointRadar>>(source);
  auto tgt = pcl::make_shared<pcl::PointCloud<PointRadar>>(pair.target);
  WeightedNDT2D<PointRadar, PointRadar> ndt;
  ndt.setResolutions({6.0f, 3.0f});
  ndt.setInputTarget(tgt);
  ndt.setInputSource(src);
  const Pose2 guess = compose(previous, integrateVelocity(v * 0.9, kSweep));  // 10 % short, as a prior might be
  pcl::PointCloud<PointRadar> rigid_out, out;
  ndt.align(rigid_out, toMatrix4<float>(guess));
  const Pose2 rigid = toPose2(ndt.getFinalTransformation());
  ndt.setSourceSweep(kSweep, previous);
  EXPECT_TRUE(ndt.hasSourceSweep());
  ndt.align(out, toMatrix4<float>(guess));
  ASSERT_TRUE(ndt.hasConverged());
  const Pose2 swept = toPose2(ndt.getFinalTransformation());
  expectClose(swept, x_true, 0.03, 0.1);
  EXPECT_GT((rigid.head<2>() - x_true.head<2>()).norm(), 0.3) << "a rigid match is not the test's point";
  // The output: each point where the cost placed it, at its world position, time offsets zeroed.
  ASSERT_EQ(out.size(), source.size());
  double err = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Pose2 world = compose(pair.source_in_target, Pose2(pair.source[i].x, pair.source[i].y, 0));
    err += std::hypot(out[i].x - world.x(), out[i].y - world.y());
    EXPECT_EQ(out[i].time_offset, 0.f);
  }
  EXPECT_LT(err / static_cast<double>(out.size()), 0.05);
  // Cleared: rigid again, the same result as before.
  ndt.clearSourceSweep();
  ndt.align(out, toMatrix4<float>(guess));
  EXPECT_EQ(toPose2(ndt.getFinalTransformation()), rigid);
}

// A sweep's first and last azimuths are a whole sweep apart in time: the voxel merge keeps them apart.
TEST(SweepCost, VoxelMergeKeepsTheSweepsEndsApart) {
  std::vector<detail::WeightedPoint2D> points{
      {10.05, 0.01, 1.0, 0.0}, {10.1, -0.01, 1.0, 0.25}, {10.06, 0.02, 1.0, 0.001}, {0.0, 10.0, 1.0, 0.1}};
  detail::SourceVoxelScratch scratch;
  detail::mergeSourceVoxelsByHalfSweep(0.25, points, scratch);
  ASSERT_EQ(points.size(), 3u);
  EXPECT_NEAR(points[0].t, 0.0005, 1e-12) << "the sweep's start, merged with its neighbour";
  EXPECT_NEAR(points[1].t, 0.1, 1e-12);
  EXPECT_NEAR(points[2].t, 0.25, 1e-12) << "the sweep's end, in its own voxel";
  EXPECT_NEAR(points[2].x, 10.1, 1e-12);
}

TEST(SweepCost, RefusesAStepItCannotUse) {
  WeightedNDT2D<PointRadar, PointRadar> ndt;
  EXPECT_THROW(ndt.setSourceSweep(0.0, Eigen::Vector3d::Zero()), std::invalid_argument);
  EXPECT_THROW(ndt.setSourceSweep(std::nan(""), Eigen::Vector3d::Zero()), std::invalid_argument);
  EXPECT_THROW(ndt.setSourceSweep(0.25, Eigen::Vector3d(0, std::nan(""), 0)), std::invalid_argument);
  EXPECT_FALSE(ndt.hasSourceSweep());
}

// WeightedNDT3D: its cost's derivatives against finite differences, the cells and weights of eq.
// (1)-(2) in 3D with each point's own covariance, known 6-DoF transforms recovered on simulated 4D
// radar scan-to-map pairs, pcl::PointXYZI through the base class (intensity as power), and the
// pcl::Registration contract (degenerate input, settings validated, output and covariance moved).
// The swap with PCL's 3D NDT and GICP is test/consumer (the installed package, the one line a user
// changes): PCL's matchers compile their whole implementation into every file that uses them.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include <pcl/registration/ndt.h>

#include "radar_ndt/frontend/point_covariance.h"
#include "radar_ndt/odometry/matcher_registry_3d.h"
#include "radar_ndt/registration/detail/ndt_cost_3d.h"
#include "radar_ndt/registration/weighted_ndt_3d.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/sim/radar_4d.h"

using namespace radar_ndt;

namespace {

using Cloud4 = pcl::PointCloud<PointRadar4D>;

double rotationErrorDeg(const Pose3& a, const Pose3& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / kPi;
}

/// A pair of the simulated 4D radar with the preset's noise scaled by `noise`.
sim::ScanToMapPair pairOf(const std::string& preset, int index, double noise = 1.0) {
  sim::ScanToMapOptions o;
  o.preset = preset;
  o.noise_scale = noise;
  return sim::scanToMapPair(o, 11, index);
}

Pose3 alignPair(pcl::Registration<PointRadar4D, PointRadar4D>& reg, const sim::ScanToMapPair& pair) {
  reg.setInputSource(Cloud4::Ptr(new Cloud4(pair.source)));
  reg.setInputTarget(Cloud4::Ptr(new Cloud4(pair.map)));
  Cloud4 out;
  reg.align(out, toMatrix4<float>(pair.guess));
  return toPose3(reg.getFinalTransformation());
}

/// Random points on three orthogonal planes (a corner of a room), weight 1, and a grid on them.
pcl::PointCloud<pcl::PointXYZ> cornerCloud(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 6.0);
  std::normal_distribution<double> noise(0.0, 0.03);
  pcl::PointCloud<pcl::PointXYZ> c;
  for (int i = 0; i < n; ++i) {
    const double a = u(rng), b = u(rng), d = noise(rng);
    pcl::PointXYZ p;
    if (i % 3 == 0) p = pcl::PointXYZ(static_cast<float>(a), static_cast<float>(b), static_cast<float>(d));
    if (i % 3 == 1) p = pcl::PointXYZ(static_cast<float>(a), static_cast<float>(d), static_cast<float>(b));
    if (i % 3 == 2) p = pcl::PointXYZ(static_cast<float>(d), static_cast<float>(a), static_cast<float>(b));
    c.push_back(p);
  }
  return c;
}

}  // namespace

TEST(NdtCost3D, GradientAndHessianMatchFiniteDifferences) {
  const auto target = cornerCloud(3000, 1);
  WeightedNDT3DSettings s;
  detail::NdtGrid3D grid;
  detail::buildNdtGrid3D(target, 1.0, s, grid);
  std::vector<detail::WeightedPoint3D> pts;
  for (const auto& p : cornerCloud(300, 2)) pts.push_back({Eigen::Vector3d(p.x, p.y, p.z), 1.0});
  Pose3 x = Pose3::Identity();
  x.linear() = expSO3(Eigen::Vector3d(0.04, -0.03, 0.05));
  x.translation() << 0.1, -0.05, 0.08;
  Vector6d g;
  Matrix6d H;
  const double f = detail::ndtCost3D(grid, pts, x, &g, &H);
  ASSERT_LT(f, -10.0);  // the points are matched
  const double h = 1e-6;
  Matrix6d numeric;
  for (int k = 0; k < 6; ++k) {
    Vector6d d = Vector6d::Zero();
    d(k) = h;
    Vector6d gp, gm;
    const double fp = detail::ndtCost3D(grid, pts, retractSE3(x, d), &gp, nullptr);
    const double fm = detail::ndtCost3D(grid, pts, retractSE3(x, -d), &gm, nullptr);
    EXPECT_NEAR(g(k), (fp - fm) / (2 * h), 1e-4 * (1 + std::abs(g(k)))) << "gradient " << k;
    numeric.col(k) = (gp - gm) / (2 * h);
  }
  // The chart's steps do not commute (exp(a) exp(b) ≠ exp(a + b) in rotation), so the finite
  // differences of the gradient differ from the symmetric Hessian by an antisymmetric part: compare
  // the symmetric parts.
  const Matrix6d sym = 0.5 * (numeric + numeric.transpose());
  EXPECT_LT((sym - H).norm(), 1e-4 * H.norm()) << "analytic\n" << H << "\nnumeric\n" << sym;
  EXPECT_LT((H - H.transpose()).norm(), 1e-12 * H.norm());
}

TEST(NdtGrid3D, CellsHoldTheirPointsCovarianceAndLookUpTheNearestBlock) {
  // Three points of weight 1 on a line along x, each with a tall own covariance (σz = 0.5 m): the
  // cell's covariance is the points' spread plus their mean covariance (eq. 1).
  Cloud4 c;
  for (float x : {0.2f, 0.5f, 0.8f}) {
    PointRadar4D p(x, 0.5f, 0.5f);
    p.cov_zz = 0.25f;
    c.push_back(p);
  }
  WeightedNDT3DSettings s;
  s.eigenvalue_ratio = 1e-6;
  detail::NdtGrid3D grid;
  detail::buildNdtGrid3D(c, 1.0, s, grid);
  ASSERT_EQ(grid.cells.size(), 1u);
  const Eigen::Matrix3d cov = grid.cells[0].inverse.inverse();
  EXPECT_NEAR(cov(0, 0), 0.06, 1e-6);  // spread of 0.2, 0.5, 0.8 (floats)
  EXPECT_NEAR(cov(2, 2), 0.25, 1e-6);  // the points' own covariance
  EXPECT_NEAR(grid.cells[0].mean.x(), 0.5, 1e-6);
  // A point is scored against the 2x2x2 block of cells nearest to it, its own among them.
  const detail::CellBlock* block = grid.cellsNear(Eigen::Vector3d(0.9, 0.9, 0.9));
  ASSERT_NE(block, nullptr);
  EXPECT_EQ(block->slots[0], 0);
  EXPECT_EQ(grid.cellsNear(Eigen::Vector3d(3.0, 0.5, 0.5)), nullptr);
  EXPECT_EQ(grid.cellsNear(Eigen::Vector3d(std::nan(""), 0, 0)), nullptr);
}

TEST(WeightedNDT3D, SourceWeightsFallWithTheirPointsUncertainty) {
  // eq. (2) in 3D: w = max(p − s, 0) · exp(−½(σx + σy + σz)); NaN points and points at or below
  // the shift are left out.
  Cloud4 c;
  PointRadar4D precise(1.f, 2.f, 3.f, 2.0f), uncertain(1.f, 2.f, 3.f, 2.0f), weak(0.f, 0.f, 0.f, 0.5f);
  uncertain.cov_xx = 0.04f;  // σx = 0.2
  uncertain.cov_yy = 0.09f;  // σy = 0.3
  uncertain.cov_zz = 1.0f;   // σz = 1 (a 4D radar's elevation)
  c.push_back(precise);
  c.push_back(uncertain);
  c.push_back(weak);
  c.push_back(PointRadar4D(std::nanf(""), 0.f, 0.f, 2.0f));
  pcl::Indices all{0, 1, 2, 3};
  std::vector<detail::WeightedPoint3D> w;
  detail::weightSourcePoints3D(c, all, 0.5, w);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_DOUBLE_EQ(w[0].w, 1.5);
  EXPECT_NEAR(w[1].w, 1.5 * std::exp(-0.5 * (0.2 + 0.3 + 1.0)), 1e-6);
}

TEST(WeightedNDT3D, RecoversKnownTransformsOfSimulated4DScans) {
  // Car presets: scan to a map of five scans, from a guess 1 m and 5° off (docs/results/matcher_3d.md
  // has the benchmark over many pairs; these pairs are recovered by every method there).
  for (const std::string preset : {"oculii_eagle", "ars548"}) {
    int recovered = 0;
    for (int k = 0; k < 4; ++k) {
      const auto pair = pairOf(preset, k);
      WeightedNDT3D<PointRadar4D, PointRadar4D> ndt;
      const Pose3 est = alignPair(ndt, pair);
      const double t_err = (est.translation() - pair.truth.translation()).norm();
      if (t_err < 0.3 && rotationErrorDeg(est, pair.truth) < 1.0) ++recovered;
      EXPECT_LT(ndt.getFinalNumIteration(), 70);
    }
    EXPECT_GE(recovered, 3) << preset;
  }
  // With the preset's noise at a tenth, the error falls with it.
  const auto pair = pairOf("oculii_eagle", 1, 0.1);
  WeightedNDT3D<PointRadar4D, PointRadar4D> ndt;
  const Pose3 est = alignPair(ndt, pair);
  EXPECT_LT((est.translation() - pair.truth.translation()).norm(), 0.05);
  EXPECT_LT(rotationErrorDeg(est, pair.truth), 0.2);
  EXPECT_TRUE(ndt.hasConverged());
  EXPECT_EQ(ndt.getResult().status, WeightedNDT3DStatus::Converged);
  // The covariance is a covariance: symmetric, positive definite, small against the error here.
  const Matrix6d& c = ndt.getPoseCovariance();
  EXPECT_LT((c - c.transpose()).norm(), 1e-9 * c.norm());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix6d>(c).eigenvalues().minCoeff(), 0.0);
  EXPECT_LT(c.diagonal().head<3>().maxCoeff(), 0.01);
}

TEST(WeightedNDT3D, XyziIntensityIsPowerThroughTheBaseClassPointer) {
  const auto pair = pairOf("oculii_eagle", 2, 0.3);
  using PointT = pcl::PointXYZI;
  auto toXYZI = [](const Cloud4& c) {
    pcl::PointCloud<PointT>::Ptr out(new pcl::PointCloud<PointT>);
    for (const auto& p : c) {
      PointT q;
      q.x = p.x;
      q.y = p.y;
      q.z = p.z;
      q.intensity = p.power;
      out->push_back(q);
    }
    return out;
  };
  const auto src = toXYZI(pair.source), tgt = toXYZI(pair.map);
  pcl::Registration<PointT, PointT>::Ptr reg(new WeightedNDT3D<PointT, PointT>);
  reg->setInputSource(src);
  reg->setInputTarget(tgt);
  pcl::PointCloud<PointT> out;
  reg->align(out, toMatrix4<float>(pair.guess));
  EXPECT_TRUE(reg->hasConverged());
  ASSERT_EQ(out.size(), src->size());
  const Pose3 est = toPose3(reg->getFinalTransformation());
  EXPECT_LT((est.translation() - pair.truth.translation()).norm(), 0.3);
  EXPECT_LT(rotationErrorDeg(est, pair.truth), 1.0);
  // The output cloud is the source moved by the result, its intensity kept.
  const Eigen::Matrix4f T = reg->getFinalTransformation();
  for (std::size_t i = 0; i < out.size(); i += 7) {
    const Eigen::Vector3f moved = T.topLeftCorner<3, 3>() * (*src)[i].getVector3fMap() + T.topRightCorner<3, 1>();
    EXPECT_LT((out[i].getVector3fMap() - moved).norm(), 1e-4f);
    EXPECT_EQ(out[i].intensity, (*src)[i].intensity);
  }
}

TEST(WeightedNDT3D, DegenerateInputIsReportedNotMatched) {
  WeightedNDT3D<PointRadar4D, PointRadar4D> ndt;
  Cloud4::Ptr empty(new Cloud4), some(new Cloud4);
  for (int i = 0; i < 50; ++i) some->push_back(PointRadar4D(0.1f * i, 1.0f, 0.5f));
  Cloud4 out;
  ndt.setInputSource(empty);
  ndt.setInputTarget(some);
  ndt.align(out);
  EXPECT_FALSE(ndt.hasConverged());
  EXPECT_TRUE(ndt.wasDegenerate());
  EXPECT_TRUE(std::isinf(ndt.getPoseCovariance()(0, 0)));
  // NaN points are left out; a source of NaN only is as empty. A line constrains too little of a
  // 6-DoF pose: degenerate.
  Cloud4::Ptr nans(new Cloud4);
  nans->push_back(PointRadar4D(std::nanf(""), 0.f, 0.f));
  ndt.setInputSource(nans);
  ndt.align(out);
  EXPECT_TRUE(ndt.wasDegenerate());
  EXPECT_EQ(ndt.getNumSourcePoints(), 0u);
  ndt.setInputSource(some);
  ndt.align(out);
  EXPECT_FALSE(ndt.hasConverged());
  EXPECT_TRUE(ndt.wasDegenerate());
  EXPECT_STREQ(toString(ndt.getResult().status), "degenerate");
}

TEST(WeightedNDT3D, SettersValidateAndChangeNothingOnError) {
  WeightedNDT3D<pcl::PointXYZ, pcl::PointXYZ> ndt;
  EXPECT_EQ(ndt.getResolutions(), (std::vector<float>{4.0f, 2.0f}));
  EXPECT_THROW(ndt.setResolution(-1.0f), std::invalid_argument);
  EXPECT_THROW(ndt.setResolutions({}), std::invalid_argument);
  EXPECT_THROW(ndt.setEigenvalueRatio(0.0), std::invalid_argument);
  EXPECT_THROW(ndt.setMinPointsPerCell(0), std::invalid_argument);
  EXPECT_THROW(ndt.setMaxStep(1.0, 0.0), std::invalid_argument);
  EXPECT_EQ(ndt.getResolutions(), (std::vector<float>{4.0f, 2.0f}));
  try {
    ndt.setSourceVoxelSize(-0.5);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("source_voxel_size"), std::string::npos) << e.what();
  }
  ndt.setResolution(1.5f);
  EXPECT_FLOAT_EQ(ndt.getResolution(), 1.5f);
}

TEST(WeightedNDT3D, OutputCovariancesTurnWithTheSource) {
  // A PointRadar4D's covariance moves with its point: a source turned by 90° about z has its tall
  // x variance in y after the match.
  const auto corner = cornerCloud(2000, 5);
  Cloud4::Ptr target(new Cloud4), source(new Cloud4);
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (const auto& p : corner) {
    target->push_back(PointRadar4D(p.x, p.y, p.z));
    const Eigen::Vector3d q = Rz.transpose() * Eigen::Vector3d(p.x, p.y, p.z);
    PointRadar4D s(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()));
    s.cov_xx = 0.01f;
    source->push_back(s);
  }
  WeightedNDT3D<PointRadar4D, PointRadar4D> ndt;
  ndt.setResolutions({2.0f, 1.0f});
  ndt.setInputSource(source);
  ndt.setInputTarget(target);
  Cloud4 out;
  Pose3 guess = Pose3::Identity();
  guess.linear() = Rz * expSO3(Eigen::Vector3d(0.02, -0.02, 0.05));
  ndt.align(out, toMatrix4<float>(guess));
  ASSERT_TRUE(ndt.hasConverged());
  EXPECT_LT(rotationErrorDeg(toPose3(ndt.getFinalTransformation()), Pose3(Rz)), 0.5);
  EXPECT_NEAR(out[0].cov_yy, 0.01f, 1e-3f);
  EXPECT_NEAR(out[0].cov_xx, 0.0f, 1e-3f);
}

TEST(SphericalCovariance, RangeAlongTheBeamAnglesAcrossIt) {
  const SphericalAccuracy a{0.1, 1.0, 4.0};
  const double deg = kPi / 180.0;
  // On the x axis at 10 m: range along x, azimuth along y (10 m × 1°), elevation along z (10 m × 4°).
  const Eigen::Matrix3d c = sphericalCovariance(Eigen::Vector3d(10, 0, 0), a);
  EXPECT_NEAR(c(0, 0), 0.01, 1e-12);
  EXPECT_NEAR(c(1, 1), std::pow(10 * deg, 2), 1e-12);
  EXPECT_NEAR(c(2, 2), std::pow(40 * deg, 2), 1e-12);
  EXPECT_NEAR(c(0, 1), 0.0, 1e-12);
  // Anywhere: the variance along the line of sight is the range's.
  const Eigen::Vector3d p(3, -4, 2);
  const Eigen::Vector3d u = p.normalized();
  EXPECT_NEAR(u.dot(sphericalCovariance(p, a) * u), 0.01, 1e-9);
  EXPECT_EQ(sphericalCovariance(Eigen::Vector3d::Zero(), a), Eigen::Matrix3d::Zero());
}

TEST(Matcher3DRegistry, EachBuiltinAlignsAPairByNameWithItsSettings) {
  // The registry's 3D matchers, made by name as the 6-DoF pipeline and radar_ndt3d_bench make them:
  // each aligns an Oculii-like pair from 1 m and 5° through pcl::Registration, with the settings
  // given (PCL's NDT at its resolution, ours at its grid), and counts its iterations.
  EXPECT_EQ(matcher3DNames(), (std::vector<std::string>{"pw-ndt-3d", "pcl-ndt-3d", "pcl-gicp"}));
  Matcher3DOptions options;
  options.ndt.resolutions = {3.0f, 1.5f};
  options.pcl_ndt_resolution = 2.5;
  const auto pair = pairOf("oculii_eagle", 0);
  for (const std::string& name : matcher3DNames()) {
    const Matcher3DEntry& e = findMatcher3D(name);
    const std::shared_ptr<Registration3D> reg = e.make(options);
    const Pose3 est = alignPair(*reg, pair);
    EXPECT_LT((est.translation() - pair.truth.translation()).norm(), 0.3) << name;
    EXPECT_LT(rotationErrorDeg(est, pair.truth), 1.0) << name;
    EXPECT_GT(e.iterations(*reg), 0) << name;
    EXPECT_EQ(e.point_covariances, name == "pw-ndt-3d");
  }
  using Ours = WeightedNDT3D<PointRadar4D, PointRadar4D>;
  using PclNdt = pcl::NormalDistributionsTransform<PointRadar4D, PointRadar4D>;
  const auto ours = findMatcher3D("pw-ndt-3d").make(options);
  EXPECT_EQ(static_cast<Ours&>(*ours).getResolutions(), options.ndt.resolutions);
  const auto pcl_ndt = findMatcher3D("pcl-ndt-3d").make(options);
  EXPECT_FLOAT_EQ(static_cast<PclNdt&>(*pcl_ndt).getResolution(), 2.5f);
}

TEST(Matcher3DRegistry, UnknownNamesAndBadEntriesAreRefusedByName) {
  try {
    findMatcher3D("gicp");
    ADD_FAILURE() << "an unknown name was found";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'gicp' (pw-ndt-3d, pcl-ndt-3d, pcl-gicp)"), std::string::npos) << e.what();
  }
  Matcher3DEntry copy = findMatcher3D("pcl-gicp");
  EXPECT_THROW(registerMatcher3D(copy), std::invalid_argument);  // the name is taken
  copy.name = "my-gicp";
  copy.iterations = nullptr;
  EXPECT_THROW(registerMatcher3D(copy), std::invalid_argument);
  copy.iterations = findMatcher3D("pcl-gicp").iterations;
  registerMatcher3D(copy);
  EXPECT_EQ(matcher3DNames().back(), "my-gicp");
  Matcher3DOptions bad;
  bad.gicp_max_correspondence = -1;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
}

TEST(Matcher3DRegistry, EachBuiltinTakesAScanSparserThanAGicpNeighbourhood) {
  // A sparse 4D scan (a TI scan holds tens of detections): PCL's GICP reads 20 neighbours of each
  // point, so the registry's pcl-gicp does not run on fewer points; every matcher returns with a
  // finite transformation and does not crash.
  const auto pair = pairOf("oculii_eagle", 0);
  pcl::PointCloud<PointRadar4D>::Ptr few(new pcl::PointCloud<PointRadar4D>);
  for (std::size_t i = 0; i < 12; ++i) few->push_back(pair.source[i * 7]);
  for (const std::string& name : matcher3DNames()) {
    const std::shared_ptr<Registration3D> reg = findMatcher3D(name).make(Matcher3DOptions{});
    reg->setInputSource(few);
    reg->setInputTarget(few);
    pcl::PointCloud<PointRadar4D> out;
    reg->align(out, Eigen::Matrix4f::Identity());
    EXPECT_TRUE(reg->getFinalTransformation().allFinite()) << name;
    if (name == "pcl-gicp") {
      EXPECT_FALSE(reg->hasConverged());
      EXPECT_TRUE(reg->getFinalTransformation().isIdentity());
    }
  }
}

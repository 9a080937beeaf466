// WeightedNDT2D's contract: aligning through the base class, its result
// (WeightedNDT2DResult and the getters that read it), degenerate input, and its settings (one
// struct, every setter validated the same way).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>
#include <pcl/console/print.h>

#include "radar_ndt/registration/weighted_ndt_2d.h"
#include "radar_ndt/se2.h"
#include "registration_support.h"

using namespace radar_ndt;
using namespace radar_ndt::test;

// The swap with PCL's ICP and NDT through the base class is test/consumer (the installed package):
// PCL's matchers compile their whole implementation into every file that uses them.
TEST(WeightedNDT2D, AlignsThroughTheBaseClassPointerAndKeepsPclsFitnessScore) {
  const auto pair = standardPair(7);
  auto src = convert<pcl::PointXYZ>(pair.source);
  auto tgt = convert<pcl::PointXYZ>(pair.target);
  pcl::Registration<pcl::PointXYZ, pcl::PointXYZ>::Ptr reg(new WeightedNDT2D<pcl::PointXYZ, pcl::PointXYZ>);
  reg->setInputSource(src);
  reg->setInputTarget(tgt);
  reg->setMaximumIterations(50);
  pcl::PointCloud<pcl::PointXYZ> out;
  reg->align(out);
  EXPECT_EQ(out.size(), src->size());
  const Pose2 p = toPose2(reg->getFinalTransformation());
  expectClose(p, pair.source_in_target, 0.02, 0.1);
  EXPECT_TRUE(reg->hasConverged());
  // pcl::Registration::getFitnessScore keeps PCL's meaning (mean squared NN distance) and works
  // although align() built no kd-tree.
  const double fitness = reg->getFitnessScore();
  EXPECT_TRUE(std::isfinite(fitness));
  EXPECT_LT(fitness, 1.0);
}

TEST(WeightedNDT2D, ReportsIterationsHessianCovarianceAndScore) {
  const auto pair = standardPair(8);
  WeightedNDT2D<PointRadar, PointRadar> ndt;
  const auto r = alignPair(pair, Pose2::Zero(), ndt);
  ASSERT_TRUE(r.converged);
  EXPECT_GT(ndt.getFinalNumIteration(), 0);
  EXPECT_LT(ndt.getFinalNumIteration(), 35);
  EXPECT_GT(ndt.getNumMatchedPoints(), pair.source.size() / 2);
  EXPECT_GT(ndt.getNdtScore(), 0.0);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> hes(ndt.getFinalHessian());
  EXPECT_GT(hes.eigenvalues().minCoeff(), 0.0) << "a maximum of the score: the Hessian of −score is PD";
  const Eigen::Matrix3d& C = ndt.getPoseCovariance();
  EXPECT_TRUE(C.allFinite());
  EXPECT_GT(C.diagonal().minCoeff(), 0.0);
  EXPECT_LT(std::sqrt(C(0, 0)), 0.05);
  EXPECT_GT(ndt.getNumCells(), 10u);
}

TEST(WeightedNDT2D, IterationLimitIsNotConvergence) {
  const auto pair = standardPair(9);
  WeightedNDT2D<PointRadar, PointRadar> ndt;
  ndt.setMaximumIterations(1);
  ndt.setTransformationEpsilon(1e-12);
  alignPair(pair, Pose2(0.8, -0.5, 0.02), ndt);
  EXPECT_FALSE(ndt.hasConverged());
  EXPECT_EQ(ndt.getFinalNumIteration(), 1);
}

TEST(WeightedNDT2D, DegenerateInputsDoNotCrash) {
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);  // the PCL_ERRORs below are expected
  using NDT = WeightedNDT2D<PointRadar, PointRadar>;
  using Cloud = pcl::PointCloud<PointRadar>;
  const auto pair = standardPair(10);
  auto run = [](const Cloud& s, const Cloud& t, NDT& ndt) {
    ndt.setInputSource(s.makeShared());
    ndt.setInputTarget(t.makeShared());
    Cloud out;
    ndt.align(out);
    EXPECT_TRUE(toPose2(ndt.getFinalTransformation()).allFinite());
    return ndt.hasConverged();
  };
  {
    NDT ndt;  // empty source
    EXPECT_FALSE(run(Cloud(), pair.target, ndt));
  }
  {
    NDT ndt;  // empty target
    EXPECT_FALSE(run(pair.source, Cloud(), ndt));
  }
  {
    NDT ndt;  // all weights zero after the shift: reported by the flags, not by a message a scan
    ndt.setPowerShift(1.5f);
    pcl::console::setVerbosityLevel(pcl::console::L_INFO);
    testing::internal::CaptureStderr();
    EXPECT_FALSE(run(pair.source, pair.target, ndt));
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    EXPECT_TRUE(ndt.wasDegenerate());
  }
  {
    NDT ndt;  // a single cell
    Cloud blob;
    for (int i = 0; i < 20; ++i) blob.push_back(PointRadar(0.1f * (i % 5), 0.1f * (i / 5), 0));
    run(blob, blob, ndt);  // either outcome, no crash
  }
  {
    NDT ndt;  // NaN and Inf points are skipped
    Cloud s = pair.source, t = pair.target;
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    s.push_back(PointRadar(nan, 1, 0));
    s.push_back(PointRadar(inf, -inf, 0));
    t.push_back(PointRadar(1, nan, 0));
    PointRadar bad_cov(3, 3, 0);
    bad_cov.cov_xx = nan;
    t.push_back(bad_cov);
    s.is_dense = t.is_dense = false;
    EXPECT_TRUE(run(s, t, ndt));
    expectClose(toPose2(ndt.getFinalTransformation()), pair.source_in_target, 0.05, 0.2);
  }
  {
    NDT ndt;  // a straight corridor: two parallel walls, nothing along them
    Cloud c;
    for (int i = 0; i < 2000; ++i) {
      c.push_back(PointRadar(-50.0f + 0.05f * i, -3.0f, 0));
      c.push_back(PointRadar(-50.0f + 0.05f * i, 3.0f, 0));
    }
    Cloud out;
    ndt.setInputSource(c.makeShared());
    ndt.setInputTarget(c.makeShared());
    ndt.align(out, toMatrix4<float>(Pose2(0.3, 0.2, 0.01)));
    const Pose2 p = toPose2(ndt.getFinalTransformation());
    ASSERT_TRUE(p.allFinite());
    // Across the corridor and in rotation it is constrained; along it the result stays sane.
    EXPECT_LT(std::abs(p.y()), 0.05);
    EXPECT_LT(std::abs(p.z()), 0.2 * kDeg);
    EXPECT_LT(std::abs(p.x()), 1.5);
  }
  pcl::console::setVerbosityLevel(pcl::console::L_INFO);
}

// One settings struct behind the PCL-style setters: what a setter writes, getSettings() shows, and
// setSettings() refuses a value out of range, naming it, without changing anything.
TEST(WeightedNDT2D, SettersWriteOneSettingsStructThatSetSettingsValidates) {
  WeightedNDT2D<PointRadar, PointRadar> ndt;
  ndt.setResolutions({6.0f, 3.0f});
  ndt.setPowerShift(0.25f);
  ndt.setShiftSourceWeights(false);
  ndt.setMinPointsPerCell(2);
  ndt.setCellLookup(CellLookup::OverlappingGrids);
  ndt.setSourceVoxelSize(0.5);
  ndt.setMaxStep(1.0, 0.1);
  const WeightedNDT2DSettings& s = ndt.getSettings();
  EXPECT_EQ(s.resolutions, (std::vector<float>{6.0f, 3.0f}));
  EXPECT_EQ(s.power_shift, 0.25f);
  EXPECT_FALSE(s.shift_source_weights);
  EXPECT_EQ(s.min_points_per_cell, 2);
  EXPECT_EQ(s.cell_lookup, CellLookup::OverlappingGrids);
  EXPECT_EQ(s.source_voxel_size, 0.5);
  EXPECT_EQ(s.max_step_translation, 1.0);
  EXPECT_EQ(s.max_step_rotation, 0.1);

  WeightedNDT2DSettings bad = s;
  bad.eigenvalue_ratio = 0.0;
  try {
    ndt.setSettings(bad);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("eigenvalue_ratio"), std::string::npos) << e.what();
  }
  EXPECT_EQ(ndt.getEigenvalueRatio(), 0.01) << "a refused setSettings changes nothing";
  for (auto breakIt : std::vector<std::function<void(WeightedNDT2DSettings&)>>{
           [](WeightedNDT2DSettings& x) { x.resolutions.clear(); },
           [](WeightedNDT2DSettings& x) { x.resolutions = {-1.0f}; },
           [](WeightedNDT2DSettings& x) { x.power_shift = std::numeric_limits<float>::quiet_NaN(); },
           [](WeightedNDT2DSettings& x) { x.min_points_per_cell = 0; },
           [](WeightedNDT2DSettings& x) { x.source_voxel_size = -0.1; },
           [](WeightedNDT2DSettings& x) { x.max_step_rotation = 0.0; },
           [](WeightedNDT2DSettings& x) { x.coarse_subsample = 0; },
           [](WeightedNDT2DSettings& x) { x.coarse_transformation_epsilon = 0.0; },
           [](WeightedNDT2DSettings& x) { x.stationary_rotation = -0.01; },
           [](WeightedNDT2DSettings& x) { x.armijo = 1.0; }, [](WeightedNDT2DSettings& x) { x.max_halvings = 0; },
           [](WeightedNDT2DSettings& x) { x.eigenvalue_floor = 0.0; },
           [](WeightedNDT2DSettings& x) { x.negligible_decrease = std::nan(""); },
           [](WeightedNDT2DSettings& x) { x.min_matched_points = 0; },
           [](WeightedNDT2DSettings& x) { x.min_information_ratio = 1.0; }}) {
    WeightedNDT2DSettings b;
    breakIt(b);
    EXPECT_THROW(b.validate(), std::invalid_argument);
  }
  WeightedNDT2DSettings good;
  good.resolutions = {4.0f};
  good.power_shift = 0.3f;
  ndt.setSettings(good);
  EXPECT_EQ(ndt.getResolution(), 4.0f);
  EXPECT_EQ(ndt.getPowerShift(), 0.3f);
}

// Every setter handles a bad value one way, as setSettings() does: std::invalid_argument naming
// the field, and nothing changed (the matcher still matches with its old settings).
TEST(WeightedNDT2D, EverySetterRefusesABadValueByThrowingAndKeepsTheOldOne) {
  using NDT = WeightedNDT2D<PointRadar, PointRadar>;
  const std::vector<std::pair<std::string, std::function<void(NDT&)>>> bad{
      {"resolutions", [](NDT& n) { n.setResolution(0.0f); }},
      {"resolutions", [](NDT& n) { n.setResolutions({}); }},
      {"power_shift", [](NDT& n) { n.setPowerShift(INFINITY); }},
      {"eigenvalue_ratio", [](NDT& n) { n.setEigenvalueRatio(1.5); }},
      {"min_points_per_cell", [](NDT& n) { n.setMinPointsPerCell(0); }},
      {"source_voxel_size", [](NDT& n) { n.setSourceVoxelSize(-0.25); }},
      {"max_step_rotation", [](NDT& n) { n.setMaxStep(1.0, 0.0); }},
      {"max_step_rotation", [](NDT& n) { n.setMaxStep(1.0, -0.1); }},
      {"max_step_rotation", [](NDT& n) { n.setMaxStep(1.0, std::nan("")); }},
      {"max_step_translation", [](NDT& n) { n.setMaxStep(INFINITY, 0.1); }},
  };
  const auto pair = standardPair(21);
  for (const auto& [field, set] : bad) {
    NDT ndt;
    const WeightedNDT2DSettings before = ndt.getSettings();
    try {
      set(ndt);
      ADD_FAILURE() << field << ": expected std::invalid_argument";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
    const WeightedNDT2DSettings& after = ndt.getSettings();
    EXPECT_EQ(after.resolutions, before.resolutions) << field;
    EXPECT_EQ(after.power_shift, before.power_shift) << field;
    EXPECT_EQ(after.eigenvalue_ratio, before.eigenvalue_ratio) << field;
    EXPECT_EQ(after.min_points_per_cell, before.min_points_per_cell) << field;
    EXPECT_EQ(after.source_voxel_size, before.source_voxel_size) << field;
    EXPECT_EQ(after.max_step_translation, before.max_step_translation) << field;
    EXPECT_EQ(after.max_step_rotation, before.max_step_rotation) << field;
    const AlignResult r = alignPair(pair, Pose2::Zero(), ndt);
    EXPECT_TRUE(r.converged) << field;
    expectClose(r.pose, pair.source_in_target, 0.02, 0.05);
  }
  NDT ndt;
  ndt.setMaxStep(0.0, 0.05);  // a translation limit <= 0: half the grid
  EXPECT_EQ(ndt.getSettings().max_step_rotation, 0.05);
  const AlignResult r = alignPair(pair, Pose2::Zero(), ndt);
  EXPECT_TRUE(r.converged);
  expectClose(r.pose, pair.source_in_target, 0.02, 0.05);
}

// One result struct after align(): what the getters report, and why the solve stopped.
TEST(WeightedNDT2D, TheResultSaysWhatAlignFoundAndWhyItStopped) {
  const auto pair = standardPair(8);
  WeightedNDT2D<PointRadar, PointRadar> ndt;
  EXPECT_EQ(ndt.getResult().status, WeightedNDT2DStatus::NotRun);
  alignPair(pair, Pose2::Zero(), ndt);
  const WeightedNDT2DResult& r = ndt.getResult();
  EXPECT_EQ(r.status, WeightedNDT2DStatus::Converged);
  EXPECT_STREQ(toString(r.status), "converged");
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.converged, ndt.hasConverged());
  EXPECT_EQ(r.final_transformation, ndt.getFinalTransformation());
  EXPECT_EQ(r.iterations, ndt.getFinalNumIteration());
  EXPECT_EQ(r.hessian, ndt.getFinalHessian());
  EXPECT_EQ(r.pose_covariance, ndt.getPoseCovariance());
  EXPECT_EQ(-r.final_cost, ndt.getNdtScore());
  EXPECT_LT(r.final_cost, 0.0);
  EXPECT_EQ(r.num_source_points, ndt.getNumSourcePoints());
  EXPECT_EQ(r.num_matched_points, ndt.getNumMatchedPoints());
  EXPECT_GT(r.num_matched_points, r.num_source_points / 2);
  EXPECT_LE(r.num_matched_points, r.num_source_points);
  EXPECT_DOUBLE_EQ(r.scorePerPoint(), ndt.getNdtScore() / static_cast<double>(ndt.getNumSourcePoints()));

  ndt.setMaximumIterations(1);
  ndt.setTransformationEpsilon(1e-12);
  alignPair(pair, Pose2(0.8, -0.5, 0.02), ndt);
  EXPECT_EQ(ndt.getResult().status, WeightedNDT2DStatus::IterationLimit);
  EXPECT_FALSE(ndt.getResult().converged);

  WeightedNDT2DSettings s;
  s.min_matched_points = static_cast<int>(pair.source.size()) + 1;  // more than there are
  WeightedNDT2D<PointRadar, PointRadar> strict;
  strict.setSettings(s);
  alignPair(pair, Pose2::Zero(), strict);
  EXPECT_EQ(strict.getResult().status, WeightedNDT2DStatus::Degenerate);
  EXPECT_TRUE(strict.wasDegenerate());
  EXPECT_TRUE(std::isinf(strict.getResult().pose_covariance(0, 0)));
}

// The solve's constants are settings the solve reads: without the subsampled phase the answer is
// the same to a millimetre, in other iterations; each Newton setting comes from its field.
TEST(WeightedNDT2D, TheSolveReadsItsSettings) {
  const auto pair = noisyPair(31, 6000);
  const Pose2 guess(0.6, -0.4, 0.01);
  WeightedNDT2D<PointRadar, PointRadar> with, without;
  WeightedNDT2DSettings s;
  s.coarse_subsample = 1;
  without.setSettings(s);
  const AlignResult a = alignPair(pair, guess, with);
  const AlignResult b = alignPair(pair, guess, without);
  ASSERT_TRUE(a.converged && b.converged);
  EXPECT_NE(with.getFinalNumIteration(), without.getFinalNumIteration());
  EXPECT_LT((a.pose - b.pose).head<2>().norm(), 1e-3);

  struct Exposed : WeightedNDT2D<PointRadar, PointRadar> {
    using WeightedNDT2D<PointRadar, PointRadar>::newtonSettings;
  };
  Exposed ndt;
  s = WeightedNDT2DSettings{};
  s.coarse_transformation_epsilon = 4e-4;
  s.coarse_rotation_epsilon = 2e-3;
  s.stationary_translation_ratio = 0.1;
  s.stationary_rotation = 0.02;
  s.armijo = 1e-3;
  s.max_halvings = 5;
  s.eigenvalue_floor = 1e-5;
  s.negligible_decrease = 1e-7;
  s.max_step_rotation = 0.3;
  ndt.setSettings(s);
  ndt.setTransformationEpsilon(1e-6);
  ndt.setTransformationRotationEpsilon(std::cos(1e-4));
  detail::NdtGrid grid;
  grid.resolution = 4.0;
  const detail::NewtonSettings coarse = ndt.newtonSettings(grid, 0, 20), fine = ndt.newtonSettings(grid, 1, 7);
  EXPECT_EQ(coarse.tolerance.translation_sq, 4e-4);
  EXPECT_EQ(coarse.tolerance.rotation_cos, std::cos(2e-3));
  EXPECT_EQ(fine.tolerance.translation_sq, 1e-6);
  EXPECT_EQ(fine.tolerance.rotation_cos, std::cos(1e-4));
  EXPECT_EQ(fine.limit.translation, 2.0) << "half the grid";
  EXPECT_EQ(fine.limit.rotation, 0.3);
  EXPECT_EQ(fine.stationary.translation, 0.4);
  EXPECT_EQ(fine.stationary.rotation, 0.02);
  EXPECT_EQ(fine.armijo, 1e-3);
  EXPECT_EQ(fine.max_halvings, 5);
  EXPECT_EQ(fine.eigenvalue_floor, 1e-5);
  EXPECT_EQ(fine.negligible_decrease, 1e-7);
  EXPECT_EQ(coarse.max_iterations, 20);
  EXPECT_EQ(fine.max_iterations, 7);
}

// pcl::Registration refuses an empty cloud and keeps the previous one; ours takes it, and align()
// reports the degenerate problem instead of matching the previous clouds again.
TEST(WeightedNDT2D, AnEmptySourceOrTargetIsDegenerateNotThePreviousCloud) {
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  using Cloud = pcl::PointCloud<PointRadar>;
  const auto pair = standardPair(22);
  for (int which = 0; which < 4; ++which) {  // empty source, empty target, null source, null target
    WeightedNDT2D<PointRadar, PointRadar> ndt;
    const AlignResult good = alignPair(pair, Pose2::Zero(), ndt);
    ASSERT_TRUE(good.converged);
    const Cloud::Ptr empty = which < 2 ? Cloud::Ptr(new Cloud) : Cloud::Ptr();
    if (which % 2 == 0)
      ndt.setInputSource(empty);
    else
      ndt.setInputTarget(empty);
    Cloud out;
    ndt.align(out, toMatrix4<float>(Pose2(0.3, 0.1, 0.01)));
    EXPECT_FALSE(ndt.hasConverged()) << which;
    EXPECT_TRUE(ndt.wasDegenerate()) << which;
    EXPECT_TRUE(toPose2(ndt.getFinalTransformation()).isApprox(Pose2(0.3, 0.1, 0.01), 1e-6))
        << which << ": a degenerate problem returns its guess, not the previous match";
  }
}

// A degenerate problem has no pose information: infinite variances, no correlations (not NaN).
TEST(WeightedNDT2D, ADegeneratePoseCovarianceIsInfiniteOnTheDiagonalAndZeroElsewhere) {
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  const auto pair = standardPair(23);
  WeightedNDT2D<PointRadar, PointRadar> ndt;
  ndt.setPowerShift(1.5f);  // every weight zero
  alignPair(pair, Pose2::Zero(), ndt);
  ASSERT_TRUE(ndt.wasDegenerate());
  const Eigen::Matrix3d& C = ndt.getPoseCovariance();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i == j)
        EXPECT_TRUE(std::isinf(C(i, j)) && C(i, j) > 0) << C;
      else
        EXPECT_EQ(C(i, j), 0.0) << C;
}

// setTransformationRotationEpsilon(≤ 0) means 1 − the transformation epsilon, as in
// pcl::IterativeClosestPoint (PCL 1.13), not "any rotation step under 90° is small": the threshold
// the solve uses is that, and a matcher given 0 or −1 stops exactly where one given 1 − ε does.
TEST(WeightedNDT2D, ARotationEpsilonThatIsNotPositiveMeansOneMinusTheTransformationEpsilon) {
  struct Exposed : WeightedNDT2D<PointRadar, PointRadar> {
    using WeightedNDT2D<PointRadar, PointRadar>::rotationEpsilon;
  };
  Exposed ndt;
  EXPECT_EQ(ndt.rotationEpsilon(), std::cos(1e-4)) << "the default";
  ndt.setTransformationEpsilon(1e-4);
  for (const double rot_eps : {0.0, -1.0}) {
    ndt.setTransformationRotationEpsilon(rot_eps);
    EXPECT_EQ(ndt.rotationEpsilon(), 1.0 - 1e-4) << rot_eps;
  }
  ndt.setTransformationRotationEpsilon(0.999);
  EXPECT_EQ(ndt.rotationEpsilon(), 0.999);

  const auto pair = noisyPair(42, 4000);
  auto run = [&](double rot_eps) {
    WeightedNDT2D<PointRadar, PointRadar> m;
    m.setTransformationEpsilon(1e-4);
    m.setTransformationRotationEpsilon(rot_eps);
    const AlignResult r = alignPair(pair, Pose2(0.5, -0.3, 0.05), m);
    return std::make_pair(r.pose, m.getFinalNumIteration());
  };
  const auto explicit_threshold = run(1.0 - 1e-4);
  for (const double rot_eps : {0.0, -1.0}) EXPECT_EQ(run(rot_eps), explicit_threshold) << rot_eps;
}

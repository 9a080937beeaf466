#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <pcl/console/print.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>

#include "radar_ndt/registration/detail/fast_exp.h"
#include "radar_ndt/registration/detail/ndt_cost.h"
#include "radar_ndt/registration/detail/ndt_grid.h"
#include "radar_ndt/registration/detail/newton_optimizer.h"
#include "radar_ndt/registration/detail/source_points.h"
#include "radar_ndt/registration/weighted_ndt_2d.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/sim/synthetic_scan.h"

using namespace radar_ndt;

namespace {

constexpr double kDeg = kPi / 180.0;

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

void expectClose(const Pose2& est, const Pose2& truth, double tol_m, double tol_deg) {
  EXPECT_LT((est.head<2>() - truth.head<2>()).norm(), tol_m)
      << "est " << est.transpose() << " truth " << truth.transpose();
  EXPECT_LT(std::abs(normalizeAngle(est.z() - truth.z())) / kDeg, tol_deg)
      << "est " << est.transpose() << " truth " << truth.transpose();
}

// Parameters: which point type, initial error (m, deg), coarse-to-fine, noisy+clutter.
struct Case {
  int point_type;  // 0 XYZ, 1 XYZI, 2 PointRadar
  double init_m;
  double init_deg;
  bool coarse_to_fine;
  bool noisy;
};

std::string caseName(const ::testing::TestParamInfo<Case>& info) {
  const char* types[] = {"XYZ", "XYZI", "PointRadar"};
  const Case& c = info.param;
  return std::string(types[c.point_type]) + "_" + std::to_string(static_cast<int>(c.init_m * 10)) + "dm_" +
         std::to_string(static_cast<int>(c.init_deg)) + "deg" + (c.coarse_to_fine ? "_c2f" : "") +
         (c.noisy ? "_noisy" : "_clean");
}

class RecoversKnownTransform : public ::testing::TestWithParam<Case> {};

template <typename PointT>
void runCase(const Case& c) {
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    SyntheticScanOptions o;
    o.points = 6000;
    o.seed = seed;
    o.max_translation = 0.0;  // the offset comes from the initial guess below
    o.max_rotation_deg = 0.0;
    if (c.noisy) {
      o.noise_std = 0.1;
      o.clutter_fraction = 0.2;
    }
    auto pair = makeSyntheticScanPair(o);
    // True pose: a random transform; the guess is the truth moved by the requested initial error.
    std::mt19937 rng(seed * 77);
    std::uniform_real_distribution<double> U(-1, 1);
    const Pose2 truth(1.5 * U(rng), 1.5 * U(rng), 3 * kDeg * U(rng));
    pcl::PointCloud<PointRadar> moved;
    const Eigen::Isometry2d T = toIsometry2(inverse(truth));
    for (auto p : pair.source) {
      const Eigen::Vector2d q = T * Eigen::Vector2d(p.x, p.y);
      p.x = static_cast<float>(q.x());
      p.y = static_cast<float>(q.y());
      moved.push_back(p);
    }
    pair.source = moved;
    const double dir = 2 * kPi * (0.5 + 0.5 * U(rng));
    const Pose2 guess = compose(
        truth, Pose2(c.init_m * std::cos(dir), c.init_m * std::sin(dir), (U(rng) > 0 ? 1 : -1) * c.init_deg * kDeg));
    WeightedNDT2D<PointT, PointT> ndt;
    if (c.coarse_to_fine) ndt.setResolutions({9.0f, 6.0f, 4.0f, 3.0f});
    if (c.noisy) ndt.setPowerShift(0.4f);  // clutter has power <= 0.3: ignored
    const auto r = alignPair(pair, guess, ndt);
    EXPECT_TRUE(r.converged) << "seed " << seed;
    if (c.noisy)
      expectClose(r.pose, truth, 0.10, 0.5);
    else
      expectClose(r.pose, truth, 0.02, 0.1);
  }
}

TEST_P(RecoversKnownTransform, WithinTolerance) {
  const Case& c = GetParam();
  switch (c.point_type) {
    case 0: runCase<pcl::PointXYZ>(c); break;
    case 1: runCase<pcl::PointXYZI>(c); break;
    default: runCase<PointRadar>(c); break;
  }
}

std::vector<Case> allCases() {
  std::vector<Case> cases;
  for (int type = 0; type < 3; ++type)
    for (bool noisy : {false, true}) {
      if (noisy && type == 0) continue;  // XYZ has no power: the clutter cannot be shifted away
      cases.push_back({type, 0.0, 0.0, false, noisy});
      cases.push_back({type, 1.0, 2.0, false, noisy});
      cases.push_back({type, 2.0, 5.0, true, noisy});
    }
  return cases;
}

INSTANTIATE_TEST_SUITE_P(WeightedNDT2D, RecoversKnownTransform, ::testing::ValuesIn(allCases()), caseName);

SyntheticScanPair standardPair(std::uint32_t seed = 5) {
  SyntheticScanOptions o;
  o.points = 6000;
  o.seed = seed;
  o.max_translation = 1.0;
  o.max_rotation_deg = 2.0;
  return makeSyntheticScanPair(o);
}

/// A pair with 5 cm of position noise on every point (default motion range).
SyntheticScanPair noisyPair(std::uint32_t seed, std::size_t points) {
  SyntheticScanOptions o;
  o.points = points;
  o.seed = seed;
  o.noise_std = 0.05;
  return makeSyntheticScanPair(o);
}

}  // namespace

TEST(WeightedNDT2D, PowerShiftIgnoresLowPowerClutterThatBiasesTheUnweightedResult) {
  // Low-power returns (power 0.25, like sidelobes and multipath) that sit on the structure in the
  // source but 10 cm off it in the target: with s = 0 they drag the cell means and bias the match;
  // with s = 0.3 their weight max(p - s, 0) is zero and the match is exact.
  auto pair = standardPair(11);
  const std::size_t n_src = pair.source.size(), n_tgt = pair.target.size();
  for (int copy = 0; copy < 2; ++copy) {
    for (std::size_t i = 0; i < n_src; ++i) {
      PointRadar p = pair.source[i];
      p.power = 0.25f;
      pair.source.push_back(p);
    }
    for (std::size_t i = 0; i < n_tgt; ++i) {
      PointRadar p = pair.target[i];
      p.x += 0.1f;
      p.power = 0.25f;
      pair.target.push_back(p);
    }
  }
  WeightedNDT2D<PointRadar, PointRadar> plain, shifted;
  shifted.setPowerShift(0.3f);
  const auto a = alignPair(pair, Pose2::Zero(), plain);
  const auto b = alignPair(pair, Pose2::Zero(), shifted);
  const double err_plain = (a.pose.head<2>() - pair.source_in_target.head<2>()).norm();
  const double err_shift = (b.pose.head<2>() - pair.source_in_target.head<2>()).norm();
  EXPECT_LT(err_shift, 0.01);
  EXPECT_GT(err_plain, 0.02) << "the low-power returns should bias the unshifted match";
}

TEST(WeightedNDT2D, SourceShiftOffWeighsTheSourceByItsUnshiftedPower) {
  // setShiftSourceWeights(false) keeps s in the cells (eq. 1) and leaves it out of the matching
  // weights (eq. 2): the same problem as shifting both with every source power raised by s. Powers
  // are multiples of 1/256 and s = 0.25, so p + s − s is exact and the answers agree bit for bit.
  auto pair = noisyPair(31, 6000);
  for (std::size_t i = 0; i < pair.target.size(); ++i)
    pair.target[i].power = 0.5f + static_cast<float>(i % 61) / 256.0f;
  pcl::PointCloud<PointRadar> raised = pair.source;
  for (std::size_t i = 0; i < pair.source.size(); ++i) {
    pair.source[i].power = 0.5f + static_cast<float>((7 * i) % 64) / 256.0f;
    raised[i].power = pair.source[i].power + 0.25f;
  }
  WeightedNDT2D<PointRadar, PointRadar> cells_only, both, both_raised;
  EXPECT_TRUE(both.getShiftSourceWeights());  // the paper's default
  for (auto* m : {&cells_only, &both, &both_raised}) m->setPowerShift(0.25f);
  cells_only.setShiftSourceWeights(false);
  const Pose2 guess(0.3, -0.2, 1.0 * kDeg);
  const auto a = alignPair(pair, guess, cells_only);
  const auto b = alignPair(pair, guess, both);
  SyntheticScanPair raised_pair = pair;
  raised_pair.source = raised;
  const auto c = alignPair(raised_pair, guess, both_raised);
  EXPECT_FALSE(cells_only.getShiftSourceWeights());
  EXPECT_TRUE(a.converged && b.converged && c.converged);
  EXPECT_EQ(a.pose, c.pose);
  EXPECT_EQ(cells_only.getNdtScore(), both_raised.getNdtScore());
  EXPECT_NE(cells_only.getNdtScore(), both.getNdtScore()) << "the source weights should differ from the shifted ones";
  expectClose(a.pose, pair.source_in_target, 0.02, 0.1);
}

TEST(WeightedNDT2D, PointsWithLargeCovariancePullLess) {
  // Half of the source is consistent with the truth; a second, shifted copy of the structure has
  // large covariance. With eq. (2) weights the consistent, precise half wins.
  auto pair = standardPair(12);
  pcl::PointCloud<PointRadar> src;
  for (const auto& p : pair.source) {
    PointRadar precise = p;
    precise.cov_xx = precise.cov_yy = 0.0004f;
    src.push_back(precise);
    PointRadar vague = p;
    vague.x += 0.8f;
    vague.cov_xx = vague.cov_yy = 16.0f;  // σ = 4 m: weight e^-4
    src.push_back(vague);
  }
  pair.source = src;
  WeightedNDT2D<PointRadar, PointRadar> ndt;
  const auto r = alignPair(pair, Pose2::Zero(), ndt);
  expectClose(r.pose, pair.source_in_target, 0.05, 0.2);
}

TEST(WeightedNDT2D, SwapsWithPclMatchersThroughTheBaseClassPointer) {
  const auto pair = standardPair(7);
  auto src = convert<pcl::PointXYZ>(pair.source);
  auto tgt = convert<pcl::PointXYZ>(pair.target);
  using Reg = pcl::Registration<pcl::PointXYZ, pcl::PointXYZ>;
  for (int which = 0; which < 3; ++which) {
    Reg::Ptr reg;
    // The one line a user changes:
    if (which == 0) reg.reset(new WeightedNDT2D<pcl::PointXYZ, pcl::PointXYZ>);
    if (which == 1) reg.reset(new pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>);
    if (which == 2) {
      auto ndt = pcl::make_shared<pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ>>();
      ndt->setResolution(3.0f);
      reg = ndt;
    }
    reg->setInputSource(src);
    reg->setInputTarget(tgt);
    reg->setMaximumIterations(50);
    pcl::PointCloud<pcl::PointXYZ> out;
    reg->align(out);
    EXPECT_EQ(out.size(), src->size()) << reg->getClassName();
    const Pose2 p = toPose2(reg->getFinalTransformation());
    EXPECT_TRUE(p.allFinite()) << reg->getClassName();
    if (which == 0) {
      expectClose(p, pair.source_in_target, 0.02, 0.1);
      EXPECT_TRUE(reg->hasConverged());
      // pcl::Registration::getFitnessScore keeps PCL's meaning (mean squared NN distance) and works
      // although align() built no kd-tree.
      const double fitness = reg->getFitnessScore();
      EXPECT_TRUE(std::isfinite(fitness));
      EXPECT_LT(fitness, 1.0);
    }
  }
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

TEST(WeightedNDT2D, OverlappingGridsAlsoRecoverTheTransform) {
  const auto pair = standardPair(13);
  WeightedNDT2D<PointRadar, PointRadar> ndt;
  ndt.setCellLookup(CellLookup::OverlappingGrids);
  const auto r = alignPair(pair, Pose2::Zero(), ndt);
  EXPECT_TRUE(r.converged);
  expectClose(r.pose, pair.source_in_target, 0.02, 0.1);
}

TEST(WeightedNDT2D, IsDeterministic) {
  const auto pair = standardPair(14);
  WeightedNDT2D<PointRadar, PointRadar> a, b;
  const auto ra = alignPair(pair, Pose2::Zero(), a);
  const auto rb = alignPair(pair, Pose2::Zero(), b);
  EXPECT_EQ(a.getFinalTransformation(), b.getFinalTransformation());
  EXPECT_EQ(ra.pose, rb.pose);
}

TEST(WeightedNDT2D, SourceVoxelMergeKeepsTheAnswer) {
  // The default merge of source points into 0.25 m weighted voxels approximates the cost; it must
  // not move the solution by more than a few millimetres against the unmerged cost.
  for (std::uint32_t seed = 20; seed < 23; ++seed) {
    const auto pair = noisyPair(seed, 8000);
    WeightedNDT2D<PointRadar, PointRadar> merged, exact;
    exact.setSourceVoxelSize(0.0);
    const auto a = alignPair(pair, Pose2::Zero(), merged);
    const auto b = alignPair(pair, Pose2::Zero(), exact);
    EXPECT_LT(merged.getNumSourcePoints(), exact.getNumSourcePoints());
    EXPECT_LT((a.pose.head<2>() - b.pose.head<2>()).norm(), 0.005) << "seed " << seed;
    EXPECT_LT(std::abs(a.pose.z() - b.pose.z()) / kDeg, 0.02) << "seed " << seed;
    expectClose(a.pose, pair.source_in_target, 0.02, 0.1);
  }
}

// The merge keys voxels in a dense table when the source's extent is compact (a scan) and in a hash
// when it is not (one far point stretches it): the same merged points in the same order, so the
// same answer bit for bit (the far point meets no cell).
TEST(WeightedNDT2D, SourceVoxelMergeIsTheSameThroughEitherTable) {
  const auto pair = noisyPair(24, 8000);
  SyntheticScanPair stretched = pair;
  PointRadar far = pair.source.front();
  far.x = 2.0e5f;
  far.y = -3.0e5f;
  stretched.source.push_back(far);
  WeightedNDT2D<PointRadar, PointRadar> dense, hashed;
  const auto a = alignPair(pair, Pose2::Zero(), dense);
  const auto b = alignPair(stretched, Pose2::Zero(), hashed);
  EXPECT_EQ(hashed.getNumSourcePoints(), dense.getNumSourcePoints() + 1);
  EXPECT_EQ(dense.getFinalTransformation(), hashed.getFinalTransformation());
  EXPECT_EQ(dense.getNdtScore(), hashed.getNdtScore());
  EXPECT_EQ(dense.getNumMatchedPoints(), hashed.getNumMatchedPoints());
  expectClose(a.pose, pair.source_in_target, 0.02, 0.1);
  EXPECT_TRUE(b.converged);
}

// The cell index answers the same through its dense table (compact keys, after finalize()) as
// through the hash (sparse keys, or after a later add()).
TEST(CellIndexHash, DenseTableAgreesWithTheHash) {
  auto fill = [](detail::CellIndexHash& h, int spread) {
    int cell = 0;
    for (int iy = -20; iy <= 20; iy += 2)
      for (int ix = -30; ix <= 30; ix += 3) h.add(ix * spread, iy, cell++);
  };
  for (const int spread : {1, 100000}) {  // 1: a dense table is built; 100000: too sparse for one
    detail::CellIndexHash hashed, dense;
    fill(hashed, spread);
    fill(dense, spread);
    dense.finalize();
    if (spread == 1) {
      EXPECT_GT(dense.memoryBytes(), hashed.memoryBytes());
    } else {
      EXPECT_EQ(dense.memoryBytes(), hashed.memoryBytes());
    }
    for (int iy = -25; iy <= 25; ++iy)
      for (int ix = -40; ix <= 40; ++ix) {
        const std::int32_t* a = hashed.find(ix * spread, iy);
        const std::int32_t* b = dense.find(ix * spread, iy);
        ASSERT_EQ(a == nullptr, b == nullptr) << ix << "," << iy;
        if (a) {
          for (int k = 0; k < 4; ++k) EXPECT_EQ(a[k], b[k]);
        }
      }
    // A key added after finalize() must be found (the dense table is dropped, not left stale).
    dense.add(1, 1, 999);
    const std::int32_t* added = dense.find(1, 1);
    ASSERT_NE(added, nullptr);
    EXPECT_EQ(added[0], 999);
  }
}

TEST(WeightedNDT2D, InlineExpMatchesLibm) {
  for (double x = -700.0; x <= 0.0; x += 0.37) {
    const double e = std::exp(x);
    EXPECT_NEAR(detail::expNegative(x), e, 1e-8 * e) << x;
  }
  EXPECT_EQ(detail::expNegative(0.0), 1.0);
  // Below the range (and NaN): as at -700, tiny and finite, never NaN or a denormal trap.
  EXPECT_EQ(detail::expNegative(-1e6), detail::expNegative(-700.0));
  EXPECT_EQ(detail::expNegative(std::numeric_limits<double>::quiet_NaN()), detail::expNegative(-700.0));
  EXPECT_GT(detail::expNegative(-700.0), 0.0);
}

namespace {
// Exposes the protected cost so its derivatives can be checked against finite differences.
class ExposedNDT : public WeightedNDT2D<PointRadar, PointRadar> {
 public:
  double cost(const Eigen::Vector3d& x, Eigen::Vector3d* g, Eigen::Matrix3d* H) {
    if (!initCompute()) return std::numeric_limits<double>::quiet_NaN();  // sets indices_
    if (model_stale_ || grids_.empty()) buildTargetModel();
    prepareSource();
    return detail::ndtCost(grids_.back(), source_points_, x, g, H);
  }
};
}  // namespace

// The analytic gradient and Hessian agree with central differences of the value, for both lookups
// (the score jumps where a point changes cells; a 1e-6 step rarely crosses one).
TEST(WeightedNDT2D, DerivativesMatchFiniteDifferences) {
  const auto pair = noisyPair(5, 3000);
  for (const CellLookup lookup : {CellLookup::Neighbours, CellLookup::OverlappingGrids}) {
    ExposedNDT ndt;
    ndt.setCellLookup(lookup);
    ndt.setSourceVoxelSize(0.0);
    ndt.setInputSource(pair.source.makeShared());
    ndt.setInputTarget(pair.target.makeShared());
    const Eigen::Vector3d x(0.3, -0.2, 0.02);
    Eigen::Vector3d g;
    Eigen::Matrix3d H;
    ndt.cost(x, &g, &H);
    const double h = 1e-6;
    Eigen::Vector3d g_fd;
    Eigen::Matrix3d H_fd;
    for (int i = 0; i < 3; ++i) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d(i) = h;
      Eigen::Vector3d gp = Eigen::Vector3d::Zero(), gm = Eigen::Vector3d::Zero();
      Eigen::Matrix3d Hp;
      g_fd(i) = (ndt.cost(x + d, &gp, &Hp) - ndt.cost(x - d, &gm, &Hp)) / (2 * h);
      H_fd.col(i) = (gp - gm) / (2 * h);
    }
    const std::string what = lookup == CellLookup::Neighbours ? "neighbours" : "overlapping grids";
    EXPECT_LT((g - g_fd).norm(), 1e-4 * g.norm() + 1e-6) << what << "\n" << g.transpose() << "\n" << g_fd.transpose();
    EXPECT_LT((H - H_fd).norm(), 1e-3 * H.norm()) << what << "\n" << H << "\n" << H_fd;
  }
}

// Mirror equivariance: with every point's y (and covariance xy) negated, the answer must be the
// mirrored one, (x, −y, −yaw), for both cell lookups. The matcher has no preferred handedness; a
// lookup or cell offset that favoured one side would show here as a mismatch (docs/notes: the
// simulated drives' yaw bias flips with the data under this mirror, so it is not the code's).
TEST(WeightedNDT2D, IsMirrorEquivariant) {
  auto mirror = [](const pcl::PointCloud<PointRadar>& in) {
    pcl::PointCloud<PointRadar> out = in;
    for (auto& p : out) {
      p.y = -p.y;
      p.cov_xy = -p.cov_xy;
    }
    return out;
  };
  for (const CellLookup lookup : {CellLookup::Neighbours, CellLookup::OverlappingGrids}) {
    for (std::uint32_t seed = 30; seed < 33; ++seed) {
      const auto pair = noisyPair(seed, 6000);
      SyntheticScanPair mirrored = pair;
      mirrored.source = mirror(pair.source);
      mirrored.target = mirror(pair.target);
      const Pose2 guess(0.3, 0.2, 0.5 * kDeg);
      WeightedNDT2D<PointRadar, PointRadar> a, b;
      a.setCellLookup(lookup);
      b.setCellLookup(lookup);
      const auto ra = alignPair(pair, guess, a);
      const auto rb = alignPair(mirrored, Pose2(guess.x(), -guess.y(), -guess.z()), b);
      ASSERT_TRUE(ra.converged && rb.converged) << "seed " << seed;
      EXPECT_NEAR(rb.pose.x(), ra.pose.x(), 1e-6) << "seed " << seed;
      EXPECT_NEAR(rb.pose.y(), -ra.pose.y(), 1e-6) << "seed " << seed;
      EXPECT_NEAR(rb.pose.z(), -ra.pose.z(), 1e-7) << "seed " << seed;
      expectClose(ra.pose, pair.source_in_target, 0.03, 0.15);
    }
  }
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
           [](WeightedNDT2DSettings& x) { x.max_step_rotation = 0.0; }}) {
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

// The inline-exp helper's macro stays inside its header.
#ifdef RADAR_NDT_ALWAYS_INLINE
#error "RADAR_NDT_ALWAYS_INLINE leaks out of radar_ndt/registration/detail/fast_exp.h"
#endif

// A rotation step limit of 0 would return the guess as converged, a negative one diverge as
// converged: both are refused and the old limits kept. A translation limit <= 0 still means half
// the grid.
TEST(WeightedNDT2D, SetMaxStepRefusesARotationLimitThatIsNotPositive) {
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);  // the PCL_ERRORs below are expected
  const auto pair = standardPair(21);
  for (const double bad : {0.0, -0.1, std::numeric_limits<double>::quiet_NaN()}) {
    WeightedNDT2D<PointRadar, PointRadar> ndt;
    ndt.setMaxStep(1.0, bad);
    EXPECT_EQ(ndt.getSettings().max_step_rotation, 0.2) << bad;
    EXPECT_EQ(ndt.getSettings().max_step_translation, -1.0) << bad;
    const AlignResult r = alignPair(pair, Pose2::Zero(), ndt);
    EXPECT_TRUE(r.converged) << bad;
    expectClose(r.pose, pair.source_in_target, 0.02, 0.05);
  }
  WeightedNDT2D<PointRadar, PointRadar> ndt;
  ndt.setMaxStep(0.0, 0.05);  // translation: half the grid
  EXPECT_EQ(ndt.getSettings().max_step_rotation, 0.05);
  const AlignResult r = alignPair(pair, Pose2::Zero(), ndt);
  EXPECT_TRUE(r.converged);
  expectClose(r.pose, pair.source_in_target, 0.02, 0.05);
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

namespace {
/// A cost whose gradient and Hessian describe a bowl with its minimum at `centre`, but whose value
/// rises by `ridge` in every direction out of the unit-radius neighbourhood of x = 0 up to `reach`
/// from it: the Newton step points at the minimum, and every step the line search tries along it
/// (down to the epsilons) scores worse, as at a cell boundary or a spurious ridge of the score.
struct TrapCost {
  Eigen::Vector3d centre;
  double reach;
  double operator()(const Eigen::Vector3d& x, Eigen::Vector3d* g, Eigen::Matrix3d* H, int*) const {
    const Eigen::Vector3d d = x - centre;
    if (g) *g = 2.0 * d;
    if (H) *H = 2.0 * Eigen::Matrix3d::Identity();
    const double moved = x.norm();
    return d.squaredNorm() + (moved > 0 && moved <= reach ? 1e3 : 0.0);
  }
};
}  // namespace

TEST(NewtonOptimizer, AFailedLineSearchIsConvergedOnlyNearTheNewtonOptimum) {
  // Away from the optimum (its Newton step 0.5 m, beyond 5 % of a 3 m cell): stuck, not converged,
  // and x stays where it was, however far the line search halved the step.
  const detail::StepTolerance tolerance{1e-6, std::cos(1e-4)};
  const detail::StepLimit limit{1.5, 0.2};
  const detail::StationaryRegion stationary{0.05 * 3.0, 0.01};
  {
    TrapCost cost{Eigen::Vector3d(0.5, 0.0, 0.0), 10.0};
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    detail::NewtonState<int> state;
    int iterations = 0, total = 0;
    EXPECT_FALSE(detail::minimizeNewton(cost, x, state, tolerance, limit, stationary, 35, &iterations, &total));
    EXPECT_EQ(x, Eigen::Vector3d::Zero());
  }
  // Near it (a 2 cm Newton step, as where points change cells at the optimum): converged.
  {
    TrapCost cost{Eigen::Vector3d(0.02, 0.0, 0.001), 10.0};
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    detail::NewtonState<int> state;
    int iterations = 0, total = 0;
    EXPECT_TRUE(detail::minimizeNewton(cost, x, state, tolerance, limit, stationary, 35, &iterations, &total));
  }
  // A plain bowl is converged, at its minimum.
  {
    TrapCost cost{Eigen::Vector3d(0.7, -0.3, 0.05), 0.0};
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    detail::NewtonState<int> state;
    int iterations = 0, total = 0;
    EXPECT_TRUE(detail::minimizeNewton(cost, x, state, tolerance, limit, stationary, 35, &iterations, &total));
    EXPECT_NEAR((x - cost.centre).norm(), 0.0, 1e-6);
  }
}

namespace {
PointRadar pointWith(float x, float y, float power, float cxx, float cxy, float cyy) {
  PointRadar p(x, y, 0.f, power);
  p.cov_xx = cxx;
  p.cov_xy = cxy;
  p.cov_yy = cyy;
  return p;
}
}  // namespace

TEST(WeightedNDT2D, CellsAreEquationOne) {
  // Eq. (1), the numbers themselves: w_i = max(p_i - s, 0), mu = sum w_i p_i / sum w_i and the
  // probabilistic covariance Sigma = sum w_i [(p_i - mu)(p_i - mu)^T + Sigma_i] / sum w_i. One
  // 4 m cell of five points, one of them below the shift (left out).
  pcl::PointCloud<PointRadar> target;
  target.push_back(pointWith(1.0f, 1.0f, 0.9f, 0.04f, 0.01f, 0.01f));
  target.push_back(pointWith(2.0f, 1.5f, 0.6f, 0.09f, 0.0f, 0.04f));
  target.push_back(pointWith(1.5f, 2.5f, 0.7f, 0.01f, -0.005f, 0.09f));
  target.push_back(pointWith(2.5f, 2.0f, 0.5f, 0.16f, 0.02f, 0.01f));
  target.push_back(pointWith(3.0f, 3.0f, 0.25f, 0.01f, 0.0f, 0.01f));
  WeightedNDT2DSettings settings;
  settings.power_shift = 0.3f;
  settings.cell_lookup = CellLookup::Neighbours;
  detail::NdtGrid grid;
  detail::buildNdtGrid(target, 4.0, settings, grid);
  ASSERT_EQ(grid.cells.size(), 1u);
  const detail::NdtCell& cell = grid.cells[0];

  double sw = 0;
  Eigen::Vector2d mu = Eigen::Vector2d::Zero();
  for (int i = 0; i < 4; ++i) {
    const double w = target[i].power - 0.3f;
    sw += w;
    mu += w * Eigen::Vector2d(target[i].x, target[i].y);
  }
  mu /= sw;
  Eigen::Matrix2d sigma = Eigen::Matrix2d::Zero();
  for (int i = 0; i < 4; ++i) {
    const double w = target[i].power - 0.3f;
    const Eigen::Vector2d d = Eigen::Vector2d(target[i].x, target[i].y) - mu;
    Eigen::Matrix2d own;
    own << target[i].cov_xx, target[i].cov_xy, target[i].cov_xy, target[i].cov_yy;
    sigma += w * (d * d.transpose() + own);
  }
  sigma /= sw;
  const Eigen::Matrix2d inv = sigma.inverse();
  EXPECT_NEAR(cell.weight, sw, 1e-6);
  EXPECT_NEAR(cell.mx, mu.x(), 1e-6);
  EXPECT_NEAR(cell.my, mu.y(), 1e-6);
  EXPECT_NEAR(cell.ixx, inv(0, 0), 1e-6 * inv.norm());
  EXPECT_NEAR(cell.ixy, inv(0, 1), 1e-6 * inv.norm());
  EXPECT_NEAR(cell.iyy, inv(1, 1), 1e-6 * inv.norm());
}

TEST(WeightedNDT2D, SourceWeightsAreEquationTwo) {
  // Eq. (2), the numbers themselves: w = max(p - s, 0) exp(-1/2 (sigma_x + sigma_y)), sigma_x and
  // sigma_y the point's standard deviations (not variances); a point below the shift is left out.
  pcl::PointCloud<PointRadar> source;
  source.push_back(pointWith(1.0f, 2.0f, 0.8f, 0.04f, 0.0f, 0.09f));  // sigma 0.2 and 0.3 m
  source.push_back(pointWith(5.0f, -1.0f, 0.5f, 0.25f, 0.1f, 1.0f));  // sigma 0.5 and 1 m
  source.push_back(pointWith(3.0f, 3.0f, 0.2f, 0.01f, 0.0f, 0.01f));  // below s
  const pcl::Indices all{0, 1, 2};
  std::vector<detail::WeightedPoint2D> out;
  detail::weightSourcePoints(source, all, 0.3, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_NEAR(out[0].w, (0.8f - 0.3) * std::exp(-0.5 * (0.2 + 0.3)), 1e-5);
  EXPECT_NEAR(out[1].w, (0.5f - 0.3) * std::exp(-0.5 * (0.5 + 1.0)), 1e-5);
  EXPECT_EQ(out[1].x, 5.0);
}

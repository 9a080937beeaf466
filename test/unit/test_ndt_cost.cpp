// detail/ndt_cost.h: the negative weighted score of eq. (2), its analytic gradient and Hessian
// against finite differences, and the matched count and information it reports.
#include <gtest/gtest.h>

#include <string>

#include "radar_ndt/registration/detail/ndt_cost.h"
#include "radar_ndt/registration/detail/ndt_grid.h"
#include "radar_ndt/registration/detail/source_points.h"
#include "registration_support.h"

using namespace radar_ndt;
using radar_ndt::test::noisyPair;
using radar_ndt::test::pointWith;

namespace {
struct Problem {
  detail::NdtGrid grid;
  std::vector<detail::WeightedPoint2D> source;
};

Problem problemOf(const SyntheticScanPair& pair, CellLookup lookup) {
  Problem p;
  WeightedNDT2DSettings settings;
  settings.cell_lookup = lookup;
  detail::buildNdtGrid(pair.target, 3.0, settings, p.grid);
  pcl::Indices all(pair.source.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<pcl::index_t>(i);
  detail::weightSourcePoints(pair.source, all, 0.0, p.source);
  return p;
}
}  // namespace

// The analytic gradient and Hessian agree with central differences of the value, for both lookups
// (the score jumps where a point changes cells; a 1e-6 step rarely crosses one).
TEST(NdtCost, DerivativesMatchFiniteDifferences) {
  const auto pair = noisyPair(5, 3000);
  for (const CellLookup lookup : {CellLookup::Neighbours, CellLookup::OverlappingGrids}) {
    const Problem p = problemOf(pair, lookup);
    auto cost = [&](const Eigen::Vector3d& x, Eigen::Vector3d* g, Eigen::Matrix3d* H) {
      return detail::ndtCost(p.grid, p.source, x, g, H);
    };
    const std::string what = lookup == CellLookup::Neighbours ? "neighbours" : "overlapping grids";
    radar_ndt::test::expectDerivativesMatchFiniteDifferences(cost, Eigen::Vector3d(0.3, -0.2, 0.02), what);
  }
}

TEST(NdtCost, OnePointOnOneCellIsItsWeightedGaussian) {
  // One cell of three points (mean (1, 1)); one source point of weight w at (1.5, 1) scored at the
  // identity: −w exp(−½ dᵀΣ⁻¹d), one matched point, information w e Jᵀ Σ⁻¹ J.
  pcl::PointCloud<PointRadar> target;
  target.push_back(pointWith(0.0f, 1.0f, 1.0f, 0.1f, 0.0f, 0.1f));
  target.push_back(pointWith(2.0f, 1.0f, 1.0f, 0.1f, 0.0f, 0.1f));
  target.push_back(pointWith(1.0f, 1.0f, 1.0f, 0.1f, 0.0f, 0.1f));
  WeightedNDT2DSettings settings;
  detail::NdtGrid grid;
  detail::buildNdtGrid(target, 4.0, settings, grid);
  ASSERT_EQ(grid.cells.size(), 1u);
  const detail::NdtCell& c = grid.cells[0];
  const std::vector<detail::WeightedPoint2D> source{{1.5, 1.0, 0.7}};
  std::size_t matched = 0;
  Eigen::Matrix3d info;
  Eigen::Vector3d g;
  Eigen::Matrix3d H;
  const double value = detail::ndtCost(grid, source, Eigen::Vector3d::Zero(), &g, &H, &matched, &info);
  const double m = 0.5 * 0.5 * c.ixx;  // d = (0.5, 0)
  const double e = 0.7 * std::exp(-0.5 * m);
  EXPECT_NEAR(value, -e, 1e-8) << "the inline exp agrees with libm to 1e-8";
  EXPECT_EQ(matched, 1u);
  EXPECT_NEAR(g.x(), e * c.ixx * 0.5, 1e-8) << "∂/∂x of −e: e · (Σ⁻¹d)_x";
  EXPECT_NEAR(info(0, 0), e * c.ixx, 1e-8);
  const double jx = -1.0, jy = 1.5;  // ∂q/∂yaw at the identity: (−y, x) of the point
  EXPECT_NEAR(info(2, 2), e * (jx * (c.ixx * jx + c.ixy * jy) + jy * (c.ixy * jx + c.iyy * jy)), 1e-8);
  // Far from every cell: nothing matched, a zero cost.
  const std::vector<detail::WeightedPoint2D> far{{50.0, 50.0, 1.0}};
  EXPECT_EQ(detail::ndtCost(grid, far, Eigen::Vector3d::Zero(), &g, &H, &matched), 0.0);
  EXPECT_EQ(matched, 0u);
  // The stride scores every stride-th point only.
  const std::vector<detail::WeightedPoint2D> two{{1.5, 1.0, 0.7}, {50.0, 50.0, 1.0}};
  EXPECT_NEAR(detail::ndtCost(grid, two, Eigen::Vector3d::Zero(), nullptr, nullptr, nullptr, nullptr, 2), -e, 1e-8);
}

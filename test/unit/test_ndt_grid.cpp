// detail/ndt_grid.h: the target model of eq. (1) as numbers, the eigenvalue floors, and the lookup
// from a point to the cells it is scored against, for both lookups.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "radar_ndt/registration/detail/ndt_grid.h"
#include "registration_support.h"

using namespace radar_ndt;
using radar_ndt::test::pointWith;

TEST(NdtGrid, CellsAreEquationOne) {
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

TEST(NdtGrid, FewPointsAreDroppedAndAFlatCellKeepsItsEigenvalueFloors) {
  // Three points on a line along x in one 4 m cell, no covariance of their own: the across-line
  // variance is zero, so it is floored at eigenvalue_ratio × the along-line variance.
  pcl::PointCloud<pcl::PointXYZ> target;
  for (const float x : {0.5f, 1.5f, 2.5f}) target.push_back(pcl::PointXYZ(x, 1.0f, 0.f));
  WeightedNDT2DSettings settings;
  settings.eigenvalue_ratio = 0.01;
  detail::NdtGrid grid;
  detail::buildNdtGrid(target, 4.0, settings, grid);
  ASSERT_EQ(grid.cells.size(), 1u);
  const double along = 2.0 / 3.0;  // variance of {0.5, 1.5, 2.5}
  EXPECT_NEAR(1.0 / grid.cells[0].ixx, along, 1e-9);
  EXPECT_NEAR(1.0 / grid.cells[0].iyy, 0.01 * along, 1e-9);
  EXPECT_NEAR(grid.cells[0].ixy, 0.0, 1e-12);
  settings.min_points_per_cell = 4;  // three points are too few
  detail::buildNdtGrid(target, 4.0, settings, grid);
  EXPECT_TRUE(grid.cells.empty());
  EXPECT_EQ(grid.cellsNear(1.0, 1.0), nullptr);
}

TEST(NdtGrid, NeighboursLookupGivesTheTwoByTwoBlockNearestThePoint) {
  // Four filled 2 m cells around the origin, one point each (min_points_per_cell 1).
  pcl::PointCloud<pcl::PointXYZ> target;
  for (const float x : {-1.0f, 1.0f})
    for (const float y : {-1.0f, 1.0f}) target.push_back(pcl::PointXYZ(x, y, 0.f));
  WeightedNDT2DSettings settings;
  settings.min_points_per_cell = 1;
  detail::NdtGrid grid;
  detail::buildNdtGrid(target, 2.0, settings, grid);
  ASSERT_EQ(grid.cells.size(), 4u);
  auto count = [&](double x, double y) {
    const std::int32_t* slots = grid.cellsNear(x, y);
    int n = 0;
    for (int k = 0; slots && k < 4; ++k) n += slots[k] >= 0;
    return n;
  };
  EXPECT_EQ(count(0.1, -0.2), 4) << "near the shared vertex: all four cells";
  EXPECT_EQ(count(1.9, 1.9), 1) << "near the outer corner of one cell: that cell alone";
  EXPECT_EQ(count(1.9, 0.2), 2) << "near an outer edge: the two cells along it";
  EXPECT_EQ(count(9.0, 9.0), 0);
  EXPECT_EQ(grid.cellsNear(std::nan(""), 0.0), nullptr);
  EXPECT_EQ(grid.cellsNear(1e12, 0.0), nullptr);
}

TEST(NdtGrid, OverlappingGridsScoreAPointAgainstItsCellInEachOfTheFourGrids) {
  // A dense 8 m square of points: every half-cell inside it lies in one cell of each of Biber's
  // four grids (shifted by half a cell in x, y and both).
  pcl::PointCloud<pcl::PointXYZ> target;
  for (float x = 0.05f; x < 8.0f; x += 0.1f)
    for (float y = 0.05f; y < 8.0f; y += 0.1f) target.push_back(pcl::PointXYZ(x, y, 0.f));
  WeightedNDT2DSettings settings;
  settings.cell_lookup = CellLookup::OverlappingGrids;
  detail::NdtGrid grid;
  detail::buildNdtGrid(target, 2.0, settings, grid);
  const std::int32_t* slots = grid.cellsNear(3.3, 4.6);
  ASSERT_NE(slots, nullptr);
  for (int k = 0; k < 4; ++k) {
    ASSERT_GE(slots[k], 0);
    const detail::NdtCell& c = grid.cells[static_cast<std::size_t>(slots[k])];
    EXPECT_LT(std::abs(c.mx - 3.3), 1.0 + 1e-6) << "cell " << k << " holds the point";
    EXPECT_LT(std::abs(c.my - 4.6), 1.0 + 1e-6) << "cell " << k << " holds the point";
  }
  EXPECT_EQ(grid.resolution, 2.0);
  EXPECT_GT(grid.memoryBytes(), grid.cells.size() * sizeof(detail::NdtCell) - 1);
}

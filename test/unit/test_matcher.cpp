// The matcher factory and adapter: each method built with its settings, and the grid, power shift
// and scores reached through the adapter by the matcher's type.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>

#include "radar_ndt/odometry/matcher.h"
#include "radar_ndt/sim/synthetic_scan.h"

using namespace radar_ndt;
using Ours = WeightedNDT2D<PointRadar, PointRadar>;
using PclNdt = pcl::NormalDistributionsTransform<PointRadar, PointRadar>;
using PclIcp = pcl::IterativeClosestPoint<PointRadar, PointRadar>;

TEST(Matcher, ParsesAndNamesEveryMethod) {
  for (const Method m : {Method::PwNdt, Method::PclNdt, Method::PclIcp, Method::Doppler, Method::RappNdt})
    EXPECT_EQ(parseMethod(toString(m)), m);
  EXPECT_THROW(parseMethod("gicp"), std::invalid_argument);
}

TEST(Matcher, TheFactoryBuildsEachMethodWithItsSettings) {
  const MatcherAdapter ours = makeMatcher(Method::PwNdt, 3.5);
  auto* ndt = dynamic_cast<Ours*>(&ours.registration());
  ASSERT_NE(ndt, nullptr);
  EXPECT_EQ(ndt->getResolution(), 3.5f);
  EXPECT_EQ(ndt->getMinPointsPerCell(), 1) << "probabilistic cells: one detection is a usable Gaussian";
  EXPECT_EQ(ndt->getMaximumIterations(), 30);
  EXPECT_EQ(ndt->getCellLookup(), CellLookup::Neighbours);
  MatcherOptions o;
  o.ours.cell_lookup = CellLookup::OverlappingGrids;
  EXPECT_EQ(dynamic_cast<Ours*>(&makeMatcher(o, 3.0).registration())->getCellLookup(), CellLookup::OverlappingGrids);

  const MatcherAdapter pcl_ndt = makeMatcher(Method::PclNdt, 2.5);
  auto* p = dynamic_cast<PclNdt*>(&pcl_ndt.registration());
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->getResolution(), 2.5f);
  EXPECT_EQ(p->getStepSize(), 0.5);
  EXPECT_EQ(p->getMaximumIterations(), 50);

  const MatcherAdapter icp = makeMatcher(Method::PclIcp, 4.0);
  ASSERT_NE(dynamic_cast<PclIcp*>(&icp.registration()), nullptr);
  EXPECT_EQ(icp.registration().getMaxCorrespondenceDistance(), 4.0);
  EXPECT_EQ(icp.registration().getMaximumIterations(), 50);

  EXPECT_FALSE(makeMatcher(Method::Doppler, 3.0)) << "no matcher: dead reckoning";
  EXPECT_THROW(makeMatcher(Method::PwNdt, 0.0), std::invalid_argument);
}

TEST(Matcher, TheAdapterChangesGridAndShiftByTheMatchersType) {
  const MatcherAdapter ours = makeMatcher(Method::PwNdt, 3.0);
  auto* ndt = dynamic_cast<Ours*>(&ours.registration());
  ours.setGrid(5.5);
  EXPECT_EQ(ndt->getResolution(), 5.5f);
  EXPECT_TRUE(ours.setPowerShift(0.25f, false));
  EXPECT_EQ(ndt->getPowerShift(), 0.25f);
  EXPECT_FALSE(ndt->getShiftSourceWeights());

  const MatcherAdapter pcl_ndt = makeMatcher(Method::PclNdt, 3.0);
  pcl_ndt.setGrid(2.0);
  EXPECT_EQ(dynamic_cast<PclNdt*>(&pcl_ndt.registration())->getResolution(), 2.0f);
  EXPECT_FALSE(pcl_ndt.setPowerShift(0.25f)) << "PCL's NDT has no power weights";
  EXPECT_TRUE(std::isnan(pcl_ndt.fitPerPoint()));

  const MatcherAdapter icp = makeMatcher(Method::PclIcp, 3.0);
  icp.setGrid(6.0);
  EXPECT_EQ(icp.registration().getMaxCorrespondenceDistance(), 6.0);
  EXPECT_FALSE(icp.setPowerShift(0.25f));

  // A user's registration, given by its own type, plugs in as "any other".
  const MatcherAdapter user(pcl::make_shared<PclIcp>());
  ASSERT_TRUE(user);
  user.setGrid(1.5);
  EXPECT_EQ(user.registration().getMaxCorrespondenceDistance(), 1.5);
}

TEST(Matcher, ScoresRankAGoodAlignmentAboveABadOne) {
  SyntheticScanOptions so;
  so.points = 3000;
  so.seed = 3;
  const SyntheticScanPair pair = makeSyntheticScanPair(so);
  for (const Method m : {Method::PwNdt, Method::PclNdt, Method::PclIcp}) {
    const MatcherAdapter a = makeMatcher(m, 3.0);
    a.registration().setInputSource(pair.source.makeShared());
    a.registration().setInputTarget(pair.target.makeShared());
    pcl::PointCloud<PointRadar> out;
    a.registration().align(out, toMatrix4<float>(pair.source_in_target));
    const double good = a.score();
    a.registration().setMaximumIterations(1);
    a.registration().align(out, toMatrix4<float>(pair.source_in_target + Pose2(1.5, -1.0, 0.1)));
    const double bad = a.score();
    EXPECT_GT(good, bad) << toString(m);
    if (m == Method::PwNdt) {
      EXPECT_GT(a.fitPerPoint(), 0.0);
      EXPECT_TRUE(std::isfinite(a.fitPerPoint()));
    }
  }
}

// The matcher options, the registry of matchers and the adapter: each method built with its
// settings, one default per radar kind, the grid and power shift applied through the adapter by
// the matcher's type, and a user's matcher registered by name.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>

#include "radar_ndt/odometry/matcher.h"
#include "radar_ndt/odometry/matcher_registry.h"
#include "radar_ndt/sim/synthetic_scan.h"

using namespace radar_ndt;
using WeightedNdt = WeightedNDT2D<PointRadar, PointRadar>;
using PclNdt = pcl::NormalDistributionsTransform<PointRadar, PointRadar>;
using PclIcp = pcl::IterativeClosestPoint<PointRadar, PointRadar>;

namespace {
MatcherOptions options(const std::string& method, double grid) {
  MatcherOptions o;
  o.method = method;
  o.grid = grid;
  return o;
}
}  // namespace

TEST(MatcherRegistry, HoldsTheBuiltInMethodsAndWhatEachUses) {
  const std::vector<std::string> names = matcherNames();
  ASSERT_GE(names.size(), 5u);
  EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + 5),
            (std::vector<std::string>{"pw-ndt", "pcl-ndt", "pcl-icp", "doppler", "rapp-ndt"}));
  EXPECT_TRUE(findMatcher("pw-ndt").uses.power_weights);
  EXPECT_TRUE(findMatcher("pw-ndt").uses.sweep_times);
  EXPECT_TRUE(findMatcher("pw-ndt").uses.merges_source);
  EXPECT_FALSE(findMatcher("pcl-ndt").uses.merges_source) << "the scanning pipeline merges PCL's sources";
  EXPECT_TRUE(findMatcher("rapp-ndt").uses.doppler_weights);
  EXPECT_TRUE(findMatcher("doppler").uses.needs_doppler);
  EXPECT_EQ(findMatcher("pcl-icp").calibration, MatchCalibration::PclIcp);
  EXPECT_THROW(findMatcher("gicp"), std::invalid_argument);
  EXPECT_NE(matcherChoices().find("pw-ndt ("), std::string::npos);
}

TEST(MatcherRegistry, AUsersMatcherIsOneRegistrationAndRefusesADuplicateName) {
  MatcherEntry e;
  e.name = "test-icp-registry";
  e.help = "ICP under another name";
  e.make = [](const MatcherOptions& o) { return MatcherAdapter(pcl::make_shared<PclIcp>(), o.nominal()); };
  registerMatcher(e);
  EXPECT_EQ(matcherNames().back(), "test-icp-registry");
  MatcherOptions o = options("test-icp-registry", 2.0);
  const MatcherAdapter a = makeMatcher(o);
  ASSERT_TRUE(a);
  EXPECT_EQ(a.registration().getMaxCorrespondenceDistance(), 2.0);
  EXPECT_THROW(registerMatcher(e), std::invalid_argument) << "a name is registered once";
  e.name = "";
  EXPECT_THROW(registerMatcher(e), std::invalid_argument);
}

TEST(MatcherOptions, OneDefaultPerRadarKindAndTheGridPowerShiftOwnedOnce) {
  const MatcherOptions scanning = MatcherOptions::forScanning(), automotive = MatcherOptions::forAutomotive();
  EXPECT_EQ(scanning.grid, 3.75);
  EXPECT_EQ(scanning.power_shift, 0.333f);
  EXPECT_EQ(scanning.weighted_ndt.cell_lookup, CellLookup::OverlappingGrids);
  EXPECT_EQ(automotive.grid, 3.0);
  EXPECT_EQ(automotive.power_shift, 0.f);
  EXPECT_EQ(automotive.weighted_ndt.cell_lookup, CellLookup::Neighbours);
  MatcherOptions o;
  o.weighted_ndt.power_shift = 0.2f;  // the power shift's one home is MatcherOptions::power_shift
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = MatcherOptions();
  o.weighted_ndt.resolutions = {4.0f};
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = MatcherOptions();
  o.method = "gicp";
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = MatcherOptions();
  o.power_shift = 1.0f;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

TEST(Matcher, TheFactoryBuildsEachMethodWithItsSettings) {
  const MatcherAdapter pw = makeMatcher(options("pw-ndt", 3.5));
  auto* ndt = dynamic_cast<WeightedNdt*>(&pw.registration());
  ASSERT_NE(ndt, nullptr);
  EXPECT_EQ(ndt->getResolution(), 3.5f);
  EXPECT_EQ(ndt->getMinPointsPerCell(), 1) << "probabilistic cells: one detection is a usable Gaussian";
  EXPECT_EQ(ndt->getMaximumIterations(), 30);
  EXPECT_EQ(ndt->getCellLookup(), CellLookup::Neighbours);
  const MatcherAdapter scanning = makeMatcher(MatcherOptions::forScanning());
  auto* s = dynamic_cast<WeightedNdt*>(&scanning.registration());
  EXPECT_EQ(s->getCellLookup(), CellLookup::OverlappingGrids);
  EXPECT_EQ(s->getPowerShift(), 0.333f);
  EXPECT_EQ(s->getResolution(), 3.75f);

  const MatcherAdapter pcl_ndt = makeMatcher(options("pcl-ndt", 2.5));
  auto* p = dynamic_cast<PclNdt*>(&pcl_ndt.registration());
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->getResolution(), 2.5f);
  EXPECT_EQ(p->getStepSize(), 0.5);
  EXPECT_EQ(p->getMaximumIterations(), 50);

  const MatcherAdapter icp = makeMatcher(options("pcl-icp", 4.0));
  ASSERT_NE(dynamic_cast<PclIcp*>(&icp.registration()), nullptr);
  EXPECT_EQ(icp.registration().getMaxCorrespondenceDistance(), 4.0);
  EXPECT_EQ(icp.registration().getMaximumIterations(), 50);

  EXPECT_FALSE(makeMatcher(options("doppler", 3.0))) << "no matcher: dead reckoning";
  EXPECT_THROW(makeMatcher(options("pw-ndt", 0.0)), std::invalid_argument);
}

TEST(Matcher, TheAdapterAppliesGridAndShiftByTheMatchersType) {
  MatcherOptions o = options("pw-ndt", 3.0);
  o.power_shift = 0.3f;
  MatcherAdapter pw = makeMatcher(o);
  auto* ndt = dynamic_cast<WeightedNdt*>(&pw.registration());
  EXPECT_TRUE(pw.hasPowerWeights());
  pw.apply({5.5, 0.15f});
  EXPECT_EQ(ndt->getResolution(), 5.5f);
  EXPECT_EQ(ndt->getPowerShift(), 0.15f);
  EXPECT_EQ(pw.current().grid, 5.5);
  EXPECT_EQ(pw.nominal().grid, 3.0) << "the nominal settings stay";
  pw.apply(pw.nominal());
  EXPECT_EQ(ndt->getResolution(), 3.0f);
  EXPECT_EQ(ndt->getPowerShift(), 0.3f);

  MatcherAdapter pcl_ndt = makeMatcher(options("pcl-ndt", 3.0));
  pcl_ndt.apply({2.0, 0.25f});
  EXPECT_EQ(dynamic_cast<PclNdt*>(&pcl_ndt.registration())->getResolution(), 2.0f);
  EXPECT_FALSE(pcl_ndt.hasPowerWeights());
  EXPECT_EQ(pcl_ndt.current().power_shift, 0.f) << "PCL's NDT has no power weights";
  EXPECT_TRUE(std::isnan(pcl_ndt.fitPerPoint()));

  MatcherAdapter icp = makeMatcher(options("pcl-icp", 3.0));
  icp.apply({6.0, 0.f});
  EXPECT_EQ(icp.registration().getMaxCorrespondenceDistance(), 6.0);

  // A user's registration, given by its own type, plugs in as "any other", at its nominal grid.
  const MatcherAdapter user(pcl::make_shared<PclIcp>(), MatchSettings{1.5, 0.f});
  ASSERT_TRUE(user);
  EXPECT_EQ(user.registration().getMaxCorrespondenceDistance(), 1.5);
}

TEST(Matcher, ScoresRankAGoodAlignmentAboveABadOne) {
  SyntheticScanOptions so;
  so.points = 3000;
  so.seed = 3;
  const SyntheticScanPair pair = makeSyntheticScanPair(so);
  for (const std::string m : {"pw-ndt", "pcl-ndt", "pcl-icp"}) {
    const MatcherAdapter a = makeMatcher(options(m, 3.0));
    a.registration().setInputSource(pair.source.makeShared());
    a.registration().setInputTarget(pair.target.makeShared());
    pcl::PointCloud<PointRadar> out;
    a.registration().align(out, toMatrix4<float>(pair.source_in_target));
    const double good = a.score();
    a.registration().setMaximumIterations(1);
    a.registration().align(out, toMatrix4<float>(pair.source_in_target + Pose2(1.5, -1.0, 0.1)));
    const double bad = a.score();
    EXPECT_GT(good, bad) << m;
    if (m == "pw-ndt") {
      EXPECT_GT(a.fitPerPoint(), 0.0);
      EXPECT_TRUE(std::isfinite(a.fitPerPoint()));
    }
  }
}

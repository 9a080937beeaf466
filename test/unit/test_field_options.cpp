// The command line made from the field tables (apps/field_options.h, apps/pipeline_options.h):
// each option sets its field as the field's type, checked against its bounds; a layout's own
// options reach only its struct; the pipelines' options are applied as radar_odometry applies them.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "command_line_support.h"
#include "field_options.h"
#include "pipeline_options.h"

using namespace radar_ndt;
using apps::FieldOption;

namespace {

template <typename R>
const FieldOption<R>& find(const std::vector<FieldOption<R>>& fields, const std::string& option,
                           const std::string& scope = "") {
  for (const auto& f : fields)
    if (f.option == option && f.scope == scope) return f;
  throw std::logic_error("no option " + option + " " + scope);
}

}  // namespace

TEST(FieldOptions, EachOptionSetsItsFieldAsItsTypeWithinItsBounds) {
  const auto fields = apps::fieldOptions(ScanningRunOptions{});
  ScanningRunOptions o;
  find(fields, "keyframe-distance").set(o, "2.5");
  EXPECT_EQ(o.odometry.keyframes.distance, 2.5);
  EXPECT_EQ(find(fields, "keyframe-distance").path, "odometry.keyframes.distance");
  EXPECT_THROW(find(fields, "keyframe-distance").set(o, "-1"), std::invalid_argument) << "below its bound";
  EXPECT_THROW(find(fields, "keyframe-distance").set(o, "2.5m"), std::invalid_argument) << "not a number";
  find(fields, "compensation-rounds").set(o, "3");
  EXPECT_EQ(o.odometry.compensation.max_rounds, 3);
  EXPECT_THROW(find(fields, "compensation-rounds").set(o, "2.5"), std::invalid_argument) << "not whole";
  find(fields, "compensation").set(o, "joint");
  EXPECT_EQ(o.odometry.compensation.mode, CompensationMode::Joint);
  EXPECT_THROW(find(fields, "compensation").set(o, "both"), std::invalid_argument);
  find(fields, "points").set(o, "polar");
  EXPECT_FALSE(o.front_end.cartesian);
  EXPECT_THROW(find(fields, "points").set(o, "true"), std::invalid_argument) << "cartesian or polar";
  EXPECT_TRUE(find(fields, "no-gate").off_switch);
  find(fields, "no-gate").set(o, "");
  EXPECT_FALSE(o.odometry.gate.enabled);
  EXPECT_EQ(find(fields, "grid").default_text, "3.75") << "the scanning radars' default";
  EXPECT_EQ(find(apps::fieldOptions(AutomotiveRunOptions{}), "grid").default_text, "3");
  AutomotiveRunOptions a;
  find(apps::fieldOptions(AutomotiveRunOptions{}), "channels").set(a, "RADAR_FRONT, RADAR_BACK_LEFT");
  EXPECT_EQ(a.sequence.channels, (std::vector<std::string>{"RADAR_FRONT", "RADAR_BACK_LEFT"}));
}

TEST(FieldOptions, ALayoutsOwnOptionsReachOnlyItsStruct) {
  const auto fields = apps::fieldOptions(ScanningRunOptions{});
  EXPECT_EQ(find(fields, "bin-size", "oxford").path, "sequence.oxford.convention.range_resolution");
  EXPECT_EQ(find(fields, "bin-size", "boreas").path, "sequence.boreas.range_resolution");
  const ScanningRunOptions boreas =
      apps::scanningOptions(test::parseOdometryCommandLine({"--format", "boreas", "--bin-size", "0.05"}));
  EXPECT_EQ(boreas.sequence.boreas.range_resolution, 0.05);
  EXPECT_EQ(boreas.sequence.oxford.convention.range_resolution,
            ScanningRunOptions().sequence.oxford.convention.range_resolution);
  const ScanningRunOptions oxford =
      apps::scanningOptions(test::parseOdometryCommandLine({"--format", "oxford", "--bin-size", "0.05"}));
  EXPECT_EQ(oxford.sequence.oxford.convention.range_resolution, 0.05);
  EXPECT_EQ(oxford.sequence.boreas.range_resolution, 0.0);
}

TEST(FieldOptions, ThePipelinesOptionsAreAppliedAsRadarOdometryAppliesThem) {
  const AutomotiveRunOptions rapp =
      apps::automotiveOptions(test::parseOdometryCommandLine({"--format", "nuscenes", "--method", "rapp-ndt"}));
  EXPECT_TRUE(rapp.odometry.doppler_weights) << "the method and what it needs, by one call";
  EXPECT_FALSE(rapp.front_end.remove_moving);
  const AutomotiveRunOptions paper = apps::automotiveOptions(
      test::parseOdometryCommandLine({"--format", "nuscenes", "--mode", "paper", "--submap", "5"}));
  EXPECT_EQ(paper.odometry.mode, AutomotiveMatchMode::SubmapToSubmap);
  EXPECT_EQ(paper.odometry.submap_size, 5u);
  EXPECT_FALSE(paper.odometry.fuse_doppler) << "the paper's scheme is not fused";
  const AutomotiveRunOptions grid =
      apps::automotiveOptions(test::parseOdometryCommandLine({"--format", "nuscenes", "--grid", "4"}));
  EXPECT_EQ(grid.matcher.grid, 4.0);
  EXPECT_THROW(apps::automotiveOptions(test::parseOdometryCommandLine({"--format", "nuscenes", "--method", "gicp"})),
               std::invalid_argument);
  const ScanningRunOptions scanning = apps::scanningOptions(
      test::parseOdometryCommandLine({"--format", "oxford", "--power-shift", "0.2", "--no-prefetch"}));
  EXPECT_EQ(scanning.matcher.power_shift, 0.2f);
  EXPECT_EQ(scanning.threads, 1);
  EXPECT_THROW(apps::scanningOptions(test::parseOdometryCommandLine({"--format", "oxford", "--method", "doppler"})),
               std::invalid_argument);
}

TEST(FieldOptions, AnOptionThatSetsNothingForTheFormatIsRefused) {
  // --threshold is the scanning front-end's; --bins is Oxford's and Boreas's, not RADIATE's.
  EXPECT_THROW(apps::automotiveOptions(test::parseOdometryCommandLine({"--format", "nuscenes", "--threshold", "0.3"})),
               std::invalid_argument);
  EXPECT_THROW(apps::scanningOptions(test::parseOdometryCommandLine({"--format", "radiate", "--bins", "10"})),
               std::invalid_argument);
  EXPECT_EQ(apps::scanningOptions(test::parseOdometryCommandLine({"--format", "boreas", "--bins", "6848"}))
                .sequence.boreas.expected_bins,
            6848u);
  EXPECT_NO_THROW(apps::automotiveOptions(test::parseOdometryCommandLine({"--format", "nuscenes", "--grid", "3"})))
      << "both pipelines'";
}

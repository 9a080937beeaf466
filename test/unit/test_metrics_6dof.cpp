// The 6-DoF metrics against rpg_trajectory_evaluation's own code: test/data/rpg_fixture holds a
// 6-DoF ground truth and estimate (TUM) and the values that project's functions (align_utils,
// compute_trajectory_errors, results_writer; fetched, run unchanged) computed on them
// (expected.json). Also: which trajectories are planar, and "all" keeping a planar file's metrics.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "radar_ndt/evaluation/metrics_6dof.h"
#include "radar_ndt/evaluation/report.h"
#include "radar_ndt/io/trajectory_io.h"

using namespace radar_ndt;

namespace {

const std::string kFixture = std::string(RADAR_NDT_TEST_DATA) + "/rpg_fixture/";

PosePairs fixturePairs() {
  return associate(readTrajectory(kFixture + "gt.txt", TrajectoryFormat::Tum),
                   readTrajectory(kFixture + "est.txt", TrajectoryFormat::Tum));
}

nlohmann::json expected() {
  std::ifstream in(kFixture + "expected.json");
  return nlohmann::json::parse(in);
}

}  // namespace

TEST(Metrics6Dof, AbsoluteErrorWithBothAlignmentsEqualsRpgs) {
  const PosePairs pairs = fixturePairs();
  ASSERT_EQ(pairs.size(), 500u);
  const auto e = expected();
  const AbsoluteError6Dof se3 = absoluteTrajectoryError6Dof(pairs, TrajectoryAlignment::SE3);
  const AbsoluteError6Dof posyaw = absoluteTrajectoryError6Dof(pairs, TrajectoryAlignment::PositionYaw);
  EXPECT_NEAR(se3.rmse_m, e["ate_se3"]["rmse_m"].get<double>(), 1e-9);
  EXPECT_NEAR(se3.rot_rmse_deg, e["ate_se3"]["rot_rmse_deg"].get<double>(), 1e-9);
  EXPECT_NEAR(posyaw.rmse_m, e["ate_posyaw"]["rmse_m"].get<double>(), 1e-9);
  EXPECT_NEAR(posyaw.rot_rmse_deg, e["ate_posyaw"]["rot_rmse_deg"].get<double>(), 1e-9);
  // Position and yaw alignment is an SE(3) alignment with fewer freedoms: never better.
  EXPECT_GT(posyaw.rmse_m, se3.rmse_m);
  EXPECT_NEAR(posyaw.alignment.linear()(2, 2), 1.0, 1e-12);
}

TEST(Metrics6Dof, RelativeErrorPerDistanceEqualsRpgs) {
  const PosePairs pairs = fixturePairs();
  const nlohmann::json all = expected();  // held: a range-for over a temporary's member dangles
  ASSERT_EQ(all["re"].size(), 4u);
  for (const auto& want : all["re"]) {
    const double d = want["distance_m"].get<double>();
    const RelativeError got = relativeError(pairs, d);
    EXPECT_EQ(got.samples, want["samples"].get<std::size_t>()) << d;
    for (const auto& [key, value] : {std::pair<const char*, double>{"trans_mean_m", got.trans_mean_m},
                                     {"trans_median_m", got.trans_median_m},
                                     {"trans_rmse_m", got.trans_rmse_m},
                                     {"trans_mean_pct", got.trans_mean_pct},
                                     {"yaw_mean_deg", got.yaw_mean_deg},
                                     {"gravity_mean_deg", got.gravity_mean_deg},
                                     {"rot_mean_deg", got.rot_mean_deg}})
      EXPECT_NEAR(value, want[key].get<double>(), 1e-9) << d << " m, " << key;
  }
  // Longer than the trajectory: no sample, nothing to average.
  EXPECT_TRUE(std::isnan(relativeError(pairs, 1000.0).trans_mean_m));
}

TEST(Metrics6Dof, FinalPositionErrorEqualsRpgsFirstPoseAlignment) {
  const FinalError f = finalPositionError(fixturePairs());
  const nlohmann::json all = expected();
  const auto& e = all["final"];
  EXPECT_NEAR(f.final_m, e["final_m"].get<double>(), 1e-9);
  EXPECT_NEAR(f.final_pct, e["final_pct"].get<double>(), 1e-9);
  EXPECT_NEAR(f.distance_m, e["distance_m"].get<double>(), 1e-9);
}

TEST(Metrics6Dof, PlanarTrajectoriesKeepTheirMetrics) {
  // A planar run (what the planar pipelines write) is planar; the fixture is not.
  PosePairs planar;
  for (int i = 0; i < 50; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.01 * i, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() << i, 0.1 * i, 0;
    planar.gt.push_back(T);
    planar.est.push_back(T);
  }
  EXPECT_TRUE(isPlanar(planar));
  EXPECT_FALSE(isPlanar(fixturePairs()));
  // "all" on a planar file: the planar metrics alone, as before; on a 6-DoF file the 6-DoF ones too.
  const EvaluationReport p = evaluate(planar, parseMetrics("all"));
  EXPECT_TRUE(p.ate.has_value());
  EXPECT_FALSE(p.ate_se3.has_value());
  EXPECT_TRUE(p.relative.empty());
  EXPECT_FALSE(p.final_error.has_value());
  EXPECT_EQ(metricsJson(p).find("ate6"), std::string::npos);
  const EvaluationReport s = evaluate(fixturePairs(), parseMetrics("all"));
  ASSERT_TRUE(s.ate_se3.has_value());
  EXPECT_EQ(s.relative.size(), 4u);
  EXPECT_TRUE(s.final_error.has_value());
  EXPECT_NE(toJson(s).find("\"posyaw\""), std::string::npos);
  // Asked by name, a 6-DoF metric is computed for any trajectory.
  EXPECT_TRUE(evaluate(planar, parseMetrics("final")).final_error.has_value());
  EXPECT_THROW(parseMetrics("ate7"), std::invalid_argument);
}

TEST(Metrics6Dof, LoopClosureErrorIsTheEndsDistanceOverThePath) {
  std::vector<Eigen::Isometry3d> loop;
  for (int i = 0; i <= 40; ++i) {  // a square of 10 m sides, ending 0.4 m from its start
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    const int side = std::min(i / 10, 3), k = i - 10 * side;
    const Eigen::Vector3d corners[] = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}, {0, 0.4, 0}};
    T.translation() = corners[side] + (corners[side + 1] - corners[side]) * (k / 10.0);
    if (i == 40) T.translation() = corners[4];
    loop.push_back(T);
  }
  EXPECT_NEAR(loopClosureErrorPct(loop), 100.0 * 0.4 / 39.6, 1e-9);
}

// The evaluation report: metric names, and the JSON every app writes.
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "radar_ndt/evaluation/report.h"

using namespace radar_ndt;

namespace {
/// A straight drive, one pose every `ds` metres, and the same drive 1 % too long.
Trajectory straight(std::size_t n, double ds, double scale = 1.0) {
  Trajectory t;
  for (std::size_t i = 0; i < n; ++i) t.poses.push_back(toIsometry3(Pose2(scale * ds * static_cast<double>(i), 0, 0)));
  return t;
}
}  // namespace

TEST(Report, ParsesMetricLists) {
  // all: the four planar metrics and the 6-DoF ones, which apply only to 6-DoF trajectories.
  EXPECT_EQ(parseMetrics("all"),
            (std::vector<Metric>{Metric::Kitti, Metric::OneMeter, Metric::Frame, Metric::Ate, Metric::SixDof}));
  EXPECT_EQ(parseMetrics("ate6,re,final").size(), 3u);
  EXPECT_EQ(parseMetrics("kitti,1m").size(), 2u);
  EXPECT_THROW(parseMetrics("kitti,rpe"), std::invalid_argument);
}

TEST(Report, JsonHasTheSharedShapeAndTheNumbers) {
  // A 1500 m straight drive estimated 1 % too long, a pose every 0.5 m: every translation error is
  // 1 % of the distance, none rotates; after the best rigid alignment the ATE is 1 % of the poses'
  // spread along the line, 0.01 · 0.5 · sqrt((n² − 1) / 12).
  const std::size_t n = 3000;
  const auto r = evaluate(associate(straight(n, 0.5), straight(n, 0.5, 1.01)), parseMetrics("all"));
  const nlohmann::json j = nlohmann::json::parse(toJson(r));
  ASSERT_TRUE(j.contains("metrics"));
  const nlohmann::json& m = j["metrics"];
  for (const char* metric : {"kitti", "1m", "frame", "ate"}) ASSERT_TRUE(m.contains(metric)) << metric;
  EXPECT_NEAR(m["kitti"]["trans_err_pct"].get<double>(), 1.0, 0.01);
  EXPECT_EQ(m["kitti"]["rot_err_deg_per_m"].get<double>(), 0.0);
  EXPECT_GT(m["kitti"]["segments"].get<std::size_t>(), 1000u);
  EXPECT_NEAR(m["1m"]["trans_err_pct"].get<double>(), 1.0, 1e-9);
  EXPECT_EQ(m["1m"]["rot_err_deg_per_m"].get<double>(), 0.0);
  EXPECT_EQ(m["1m"]["segments"].get<std::size_t>(), n - 2);
  EXPECT_NEAR(m["frame"]["trans_err_m"].get<double>(), 0.005, 1e-12);
  EXPECT_EQ(m["frame"]["rot_err_deg"].get<double>(), 0.0);
  EXPECT_EQ(m["frame"]["pairs"].get<std::size_t>(), n - 1);
  const double nd = static_cast<double>(n);
  EXPECT_NEAR(m["ate"]["rmse_m"].get<double>(), 0.01 * 0.5 * std::sqrt((nd * nd - 1.0) / 12.0), 1e-6);
  // The JSON says what the report holds, number for number.
  EXPECT_EQ(m["kitti"]["trans_err_pct"].get<double>(), r.kitti->trans_err_pct);
  EXPECT_EQ(m["ate"]["rmse_m"].get<double>(), r.ate->rmse_m);
}

TEST(Report, MeanAveragesEachErrorWhereItIsDefinedAndSumsCounts) {
  EvaluationReport a, b;
  a.frame = FrameError{0.1, 0.2, 10};
  b.frame = FrameError{0.3, kUndefinedError, 5};
  a.one_meter = SegmentError();
  a.one_meter->trans_err_pct = 2.0;
  a.one_meter->segments = 7;
  b.one_meter = SegmentError();  // nothing to average: undefined
  const EvaluationReport m = meanReport({a, b});
  ASSERT_TRUE(m.frame);
  EXPECT_DOUBLE_EQ(m.frame->trans_err_m, 0.2);
  EXPECT_DOUBLE_EQ(m.frame->rot_err_deg, 0.2) << "an undefined error does not pull the mean";
  EXPECT_EQ(m.frame->pairs, 15u);
  ASSERT_TRUE(m.one_meter);
  EXPECT_DOUBLE_EQ(m.one_meter->trans_err_pct, 2.0);
  EXPECT_EQ(m.one_meter->segments, 7u);
  EXPECT_FALSE(m.kitti) << "a metric no run has is not invented";
  const nlohmann::json j = nlohmann::json::parse(metricsJson(m));
  EXPECT_TRUE(j["1m"]["rot_err_deg_per_m"].is_null()) << "undefined is null in JSON, never 0";
}

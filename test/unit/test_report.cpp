// The evaluation report: metric names, and the JSON every app writes.
#include <gtest/gtest.h>

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
  EXPECT_EQ(parseMetrics("all").size(), 4u);
  EXPECT_EQ(parseMetrics("kitti,1m").size(), 2u);
  EXPECT_THROW(parseMetrics("kitti,rpe"), std::invalid_argument);
}

TEST(Report, JsonHasTheSharedShape) {
  const auto r = evaluate(associate(straight(3000, 0.5), straight(3000, 0.5, 1.01)), parseMetrics("all"));
  const std::string j = toJson(r);
  for (const char* key :
       {"\"metrics\"", "\"kitti\"", "\"1m\"", "\"frame\"", "\"ate\"", "\"trans_err_pct\"", "\"rot_err_deg_per_m\"",
        "\"segments\"", "\"trans_err_m\"", "\"rot_err_deg\"", "\"pairs\"", "\"rmse_m\""})
    EXPECT_NE(j.find(key), std::string::npos) << key;
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

#pragma once
// radar_batch's report: one row per task from its result.json, the means and medians per method
// and setting over the sequences, the best setting per method, and the files (summary.csv,
// summary.md, summary.svg). The same results give the same bytes.

#include <limits>
#include <string>
#include <vector>

#include "batch_plan.h"
#include "batch_run.h"

namespace radar_ndt {
namespace batch {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

/// The figures a report keeps of a task (NaN where the run has none: no ground truth, a metric
/// undefined on a short sequence, a failed task).
struct TaskRow {
  Task task;
  TaskState state = TaskState::Missing;
  int exit_code = -1;
  double kitti_pct = kNone, kitti_deg_per_m = kNone, one_meter_pct = kNone, one_meter_deg_per_m = kNone;
  double frame_m = kNone, frame_deg = kNone, ate_m = kNone;
  /// 6-DoF runs: ATE with position + yaw and with SE(3) alignment, the relative error's mean
  /// translation in % of the distance over its distances, the final position error in %.
  double ate_posyaw_m = kNone, ate_posyaw_deg = kNone, ate_se3_m = kNone, re_pct = kNone, final_pct = kNone;
  double scans = kNone, fallbacks = kNone, problems = kNone, ms_per_scan = kNone;
  std::string log;  ///< the task's log, relative to the run folder
};

/// The rows of every task of `plan`, in plan order.
std::vector<TaskRow> collectRows(const Plan& plan);

/// The metric columns, in report order: name and the row's value; the 6-DoF runs' columns are in
/// summary.csv only when a task has one (a planar run's file is as it was).
struct MetricColumn {
  const char* name;
  double TaskRow::*field;
  bool six_dof = false;
};
const std::vector<MetricColumn>& metricColumns();

/// One method and setting over the sequences: per metric column, the mean and median of the
/// complete tasks where it is defined (NaN where none is), and how many tasks are complete.
struct GroupSummary {
  std::string method, settings;
  std::size_t tasks = 0, complete = 0;
  std::vector<double> mean, median;  ///< by metricColumns()
};
std::vector<GroupSummary> summarize(const std::vector<TaskRow>& rows);

/// The metric column the best setting is chosen by: the first of ATE m with position + yaw
/// alignment (6-DoF runs), KITTI %, 1 m %, ATE m and frame m defined for every complete task (-1:
/// none), so every setting is judged on the same sequences.
int primaryMetric(const std::vector<TaskRow>& rows);

std::string summaryCsv(const std::vector<TaskRow>& rows);
std::string summaryMarkdown(const Plan& plan, const std::vector<TaskRow>& rows);
/// Per sequence, the primary metric of each method and setting as grouped bars.
std::string summarySvg(const std::vector<TaskRow>& rows);

/// A number as the report writes it: 9 significant digits, "" for NaN.
std::string formatNumber(double v);

}  // namespace batch
}  // namespace radar_ndt

#pragma once
// Computes a chosen set of metrics and renders them the same way in every app: a readable table,
// and JSON of the shape
//   {"metrics": {"kitti": {"trans_err_pct", "rot_err_deg_per_m", "segments"},
//                "1m":    {"trans_err_pct", "rot_err_deg_per_m", "segments"},
//                "frame": {"trans_err_m", "rot_err_deg", "pairs"},
//                "ate":   {"rmse_m"},
//                "ate6":  {"se3": {"rmse_m", "rot_rmse_deg"}, "posyaw": {...}, "poses"},
//                "re":    [{"distance_m", "samples", "trans_mean_m", "trans_median_m", "trans_rmse_m",
//                           "trans_mean_pct", "yaw_mean_deg", "gravity_mean_deg", "rot_mean_deg"}, ...],
//                "final": {"final_m", "final_pct", "distance_m"}}}
// with one entry per computed metric.

#include <optional>
#include <string>
#include <vector>

#include "radar_ndt/evaluation/metrics.h"
#include "radar_ndt/evaluation/metrics_6dof.h"
#include "radar_ndt/fields.h"

namespace radar_ndt {

/// Ate is the x-y ATE after an SE(2) alignment (metrics.h); Ate6Dof, Relative and Final are the
/// 6-DoF metrics (metrics_6dof.h); SixDof stands for those three on 6-DoF trajectories and nothing
/// on planar ones (what "all" adds: planar files keep their metrics).
enum class Metric { Kitti, OneMeter, Frame, Ate, Ate6Dof, Relative, Final, SixDof };

/// Parses "kitti", "1m", "frame", "ate", "ate6", "re", "final", "all", or a comma-separated list
/// of them. Throws std::invalid_argument naming the bad word.
std::vector<Metric> parseMetrics(const std::string& text);

struct EvaluationOptions {
  std::vector<double> kitti_lengths{100, 200, 300, 400, 500, 600, 700, 800};
  std::size_t kitti_step = 10;
  double one_meter_length = 1.0;
  std::size_t frame_step = 1;
  /// The relative error's sub-trajectory lengths (rpg's; a hand-held rig's), and how far a
  /// sub-trajectory's length may be from them, as a share of the length (rpg's 0.2).
  std::vector<double> re_distances{10, 20, 50, 100};
  double re_max_difference = 0.2;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void EvaluationOptions::fields(Visit&& visit) {
  using S = EvaluationOptions;
  visit(&S::kitti_lengths, Field("kitti_lengths", "the KITTI metric's segment lengths").unit("m").positive());
  visit(&S::kitti_step, Field("kitti_step", "the KITTI metric's first frames every this many poses").atLeast(1));
  visit(&S::one_meter_length, Field("one_meter_length", "the 1 m metric's segment length").unit("m").positive());
  visit(&S::frame_step, Field("frame_step", "the frame metric's step in poses").atLeast(1));
  visit(&S::re_distances, Field("re_distances", "the relative error's sub-trajectory lengths").unit("m").positive());
  visit(&S::re_max_difference,
        Field("re_max_difference", "a sub-trajectory's length within this share of the asked one").positive());
}

struct EvaluationReport {
  std::size_t associated_poses = 0;
  std::optional<SegmentError> kitti;
  std::optional<SegmentError> one_meter;
  std::optional<FrameError> frame;
  std::optional<AbsoluteError> ate;
  std::optional<AbsoluteError6Dof> ate_se3, ate_posyaw;
  std::vector<RelativeError> relative;  ///< one per re_distances entry, when asked
  std::optional<FinalError> final_error;
};

EvaluationReport evaluate(const PosePairs& pairs, const std::vector<Metric>& metrics,
                          const EvaluationOptions& options = EvaluationOptions());

/// The mean of several runs' reports (e.g. one per scene), for the metrics all of them have: each
/// error averaged over the runs where it is defined (NaN where none is), segment, pair and pose
/// counts summed, the KITTI per-length rows averaged row by row.
EvaluationReport meanReport(const std::vector<EvaluationReport>& reports);

/// The value of the "metrics" key: {"kitti": {...}, ...}, for apps that add their own keys.
std::string metricsJson(const EvaluationReport& report);
/// {"metrics": {...}}
std::string toJson(const EvaluationReport& report);
/// A readable table, one row per metric.
std::string formatTable(const EvaluationReport& report);

}  // namespace radar_ndt

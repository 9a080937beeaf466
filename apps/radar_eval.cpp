// radar_eval: odometry metrics of an estimated trajectory against ground truth.
#include <cstdio>
#include <iostream>

#include <pcl/console/time.h>

#include "app_common.h"
#include "radar_ndt/evaluation/metrics.h"
#include "radar_ndt/evaluation/report.h"
#include "radar_ndt/evaluation/svg_plot.h"
#include "radar_ndt/field_values.h"
#include "radar_ndt/io/trajectory_io.h"

using namespace radar_ndt;
namespace po = boost::program_options;

namespace {

/// --kitti-step: a count >= 1, or auto: 4 when the estimate is a Boreas odometry file (pyboreas
/// compute_kitti_metrics takes step 4 for its radar benchmark, 10 for lidar and KITTI), else 10.
std::size_t kittiStep(const std::string& text, const std::string& est_path, TrajectoryFormat format) {
  if (text == "auto") {
    if (format == TrajectoryFormat::Auto) format = detectTrajectoryFormat(est_path);
    return format == TrajectoryFormat::Boreas ? 4 : 10;
  }
  std::size_t used = 0;
  unsigned long long v = 0;
  try {
    v = std::stoull(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || text[0] == '-' || v == 0)
    throw std::invalid_argument("--kitti-step must be auto or a count >= 1, not '" + text + "'");
  return static_cast<std::size_t>(v);
}

/// Reads a trajectory and says how many of its rotation blocks were rounded off orthonormal and
/// projected.
Trajectory readReported(const std::string& path, TrajectoryFormat format) {
  Trajectory t = readTrajectory(path, format);
  if (t.projected_rotations > 0)
    pcl::console::print_warn(
        "%s: %zu of %zu rotation blocks are not orthonormal (max |RtR - I| = %.2g, a file rounded to few "
        "decimals): projected onto rotations\n",
        path.c_str(), t.projected_rotations, t.size(), t.max_rotation_deviation);
  return t;
}

/// --re-distances through the field's own parser and bounds.
void setReDistances(EvaluationOptions& options, const std::string& text) {
  const FieldEntry<EvaluationOptions>* re = findFieldEntry<EvaluationOptions>("re_distances");
  re->set(options, re->parse(text, "--re-distances"), "--re-distances");
}

/// The command line's values.
struct Args {
  std::string gt_path, est_path, metric_text, plot_path, format_text, kitti_step_text, re_text;
  std::size_t frame_step = 1;
  double one_m = 1.0;
  bool json = false;
};

po::options_description describe(Args& a) {
  po::options_description opts("Options");
  // clang-format off
  opts.add_options()
    ("help,h", "print this help and exit")
    ("gt", po::value(&a.gt_path)->required(), "ground-truth trajectory (KITTI, TUM, Boreas odometry, or a Boreas applanix/*_poses.csv)")
    ("est", po::value(&a.est_path)->required(), "estimated trajectory (KITTI, TUM or Boreas odometry)")
    ("format", po::value(&a.format_text)->default_value("auto"),
     "file format of both: auto|kitti|tum|boreas (auto: a Boreas pose CSV by its GPSTime header, else 12 "
     "columns KITTI, 8 TUM, 13 Boreas odometry)")
    ("metric", po::value(&a.metric_text)->default_value("kitti"),
     "kitti|1m|frame|ate|ate6|re|final|all, or a comma-separated list (ate6, re, final: the 6-DoF metrics, "
     "which all adds for a trajectory that leaves the plane)")
    ("re-distances", po::value(&a.re_text)->default_value("10,20,50,100"),
     "re: the sub-trajectory lengths (m), comma-separated (rpg_trajectory_evaluation's relative error)")
    ("kitti-step", po::value(&a.kitti_step_text)->default_value("auto"),
     "kitti: a first frame every N poses; auto: 4 for Boreas odometry files (the Boreas SDK's radar "
     "benchmark), else 10 (KITTI's)")
    ("segment-length", po::value(&a.one_m)->default_value(1.0), "1m: segment length (m)")
    ("frame-step", po::value(&a.frame_step)->default_value(1), "frame: compare poses i and i+N (N > 1 subsamples)")
    ("json", po::bool_switch(&a.json), "print one JSON object {\"metrics\": {...}} instead of the table")
    ("plot", po::value(&a.plot_path), "write an SVG: both trajectories (top view) and the error per segment length");
  // clang-format on
  return opts;
}

const char* const kUsage =
    "Usage: radar_eval --gt GT --est EST [--metric kitti|1m|frame|ate|ate6|re|final|all] [--json] [--plot out.svg]\n"
    "Association: by index when either file has no timestamps (KITTI; equal lengths needed), else by\n"
    "timestamp with the ground truth interpolated. Rotation blocks rounded off orthonormal (files with\n"
    "few decimals) are projected onto rotations and reported. A trajectory that leaves the plane (z, roll or\n"
    "pitch) is 6-DoF: all adds rpg_trajectory_evaluation's ATE (SE(3) and position + yaw alignment) and\n"
    "relative error, and the final position error. Metrics: docs/metrics.md.";

}  // namespace

int main(int argc, char** argv) {
  Args a;
  const po::options_description opts = describe(a);
  po::variables_map vm;
  const int rc = apps::parseCommandLine(argc, argv, opts, kUsage, vm);
  if (rc >= 0) return rc;

  return apps::runGuarded("radar_eval", [&]() {
    pcl::console::TicToc timer;
    timer.tic();
    const std::vector<Metric> metrics = parseMetrics(a.metric_text);
    const TrajectoryFormat format = parseTrajectoryFormat(a.format_text);
    if (a.frame_step == 0) throw std::invalid_argument("--frame-step must be >= 1");
    const Trajectory gt = readReported(a.gt_path, format);
    const Trajectory est = readReported(a.est_path, format);
    const PosePairs pairs = associate(gt, est);
    EvaluationOptions options;
    options.kitti_step = kittiStep(a.kitti_step_text, a.est_path, format);
    options.one_meter_length = a.one_m;
    options.frame_step = a.frame_step;
    setReDistances(options, a.re_text);
    const EvaluationReport report = evaluate(pairs, metrics, options);
    if (a.json) {
      std::cout << toJson(report) << std::endl;
    } else {
      pcl::console::print_info("Evaluated %zu associated poses (%s) in %.0f ms\n", pairs.size(),
                               pairs.stamps.empty() ? "by index" : "by timestamp", timer.toc());
      std::cout << formatTable(report);
    }
    if (!a.plot_path.empty()) {
      writeEvaluationSvg(a.plot_path, pairs, report, a.est_path + " vs " + a.gt_path);
      if (!a.json) pcl::console::print_info("Wrote %s\n", a.plot_path.c_str());
    }
    return 0;
  });
}

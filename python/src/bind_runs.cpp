// Whole runs as radar_odometry runs them (the same defaults for the sequence's radar, the same
// pipelines), and the metrics on trajectories.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>  // paths as str or os.PathLike

#include "bindings.h"
#include "keywords.h"
#include "radar_ndt/evaluation/report.h"
#include "radar_ndt/evaluation/run_report.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/pipeline/automotive_run.h"
#ifdef RADAR_NDT_WITH_ROS
#include "radar_ndt/ros/rosbag_scans.h"
#include "radar_ndt/ros/rosbag_sequence.h"
#endif
#include "radar_ndt/pipeline/scanning_run.h"

namespace radar_ndt {
namespace python {

namespace {

py::object jsonToPython(const std::string& text) {
  return py::module_::import("json").attr("loads")(text);
}

/// The run's summary as radar_odometry --json gives it: summaryJson, and when `metrics` names any
/// ("default": the app's default for the pipeline) and the run has ground truth, the metrics and
/// the frame error of the method's own prior beside them.
template <typename Result>
py::dict summaryOf(const Result& r, const std::string& metrics) {
  if (metrics.empty() || r.ground_truth.empty()) return py::reinterpret_borrow<py::dict>(jsonToPython(summaryJson(r)));
  const EvaluationReport report =
      evaluate(associate(r.ground_truth, r.estimate), metrics == "default" ? defaultMetrics(r) : parseMetrics(metrics));
  py::dict out = py::reinterpret_borrow<py::dict>(jsonToPython(summaryJson(r, &report)));
  const FrameError prior = priorFrameError(r.steps, r.ground_truth);
  if (prior.pairs > 0) {
    py::dict p;
    p["prior"] = std::is_same_v<Result, ScanningRunResult> ? "constant velocity" : "Doppler ego-motion";
    p["trans_err_m"] = prior.trans_err_m;
    p["rot_err_deg"] = prior.rot_err_deg;
    p["pairs"] = prior.pairs;
    out["prior_frame"] = p;
  }
  return out;
}

/// `base` with the keywords applied, `method` (a shortcut for matcher.method) last, validated: the
/// options run_scanning runs with, and what scanning_options shows.
ScanningRunOptions scanningKeywords(const ScanningRunOptions& base, const py::kwargs& kw) {
  ScanningRunOptions o = withKeywords(base, without(kw, {"method"}), "ScanningRunOptions", "method");
  if (kw.contains("method")) o.matcher.method = keywordAs<std::string>(kw["method"], "method");
  o.validate();
  return o;
}

/// The parts of a run result both pipelines have, and the summary.
template <typename Result>
void bindRunResult(py::class_<Result>& c) {
  c.def_readonly("estimate", &Result::estimate, "the estimated Trajectory (first pose identity, stamps in s)")
      .def_readonly("ground_truth", &Result::ground_truth, "the dataset's, relative to the first pose; may be empty")
      .def_readonly("steps", &Result::steps)
      .def_readonly("problems", &Result::problems)
      .def_readonly("prior", &Result::prior,
                    "what each step's initial guess came from (constant velocity, Doppler, gyro, ...)")
      .def_readonly("period", &Result::period_s)
      .def_readonly("median_total_ms", &Result::median_total_ms)
      .def_readonly("method", &Result::method)
      .def_property_readonly("median_ms",
                             [](const Result& r) {
                               py::dict d;
                               d["read"] = r.median_ms.read_ms;
                               d["front_end"] = r.median_ms.front_end_ms;
                               d["submap"] = r.median_ms.submap_ms;
                               d["match"] = r.median_ms.match_ms;
                               return d;
                             })
      .def_property_readonly(
          "stamps", [](const Result& r) { return stampsArray(r.estimate); }, "numpy.ndarray: (N,) estimate stamps (s)")
      .def_property_readonly(
          "poses", [](const Result& r) { return posesArray(r.estimate); }, "numpy.ndarray: (N, 4, 4) estimated poses")
      .def(
          "summary", [](const Result& r, const std::string& metrics) { return summaryOf(r, metrics); },
          py::arg("metrics") = "",
          "The run summary as radar_odometry --json gives it, as a dict; metrics ('kitti,frame', 'all', "
          "'default', ...) adds them against the ground truth, with the prior's frame error beside them "
          "(prior_frame), as --eval does.")
      .def(
          "steps_csv", [](const Result& r) { return stepsCsv(r); },
          "The per-step CSV radar_odometry --steps writes, as text.");
}

}  // namespace

void bindRunResults(py::module_& m) {
  py::class_<ScanningRunResult> scanning(m, "ScanningRun", "What run_scanning returns.");
  bindRunResult(scanning);
  scanning.def_readonly("sequence", &ScanningRunResult::sequence)
      .def_readonly("format", &ScanningRunResult::format,
                    "the layout the scans came from: oxford, radiate, boreas, rosbag")
      .def_readonly("scans_per_second", &ScanningRunResult::scans_per_second)
      .def_readonly("wall_s", &ScanningRunResult::wall_s)
      .def_readonly("threads", &ScanningRunResult::threads);
  py::class_<AutomotiveRunResult> automotive(m, "AutomotiveRun", "What run_automotive returns.");
  bindRunResult(automotive);
  automotive.def_readonly("scene", &AutomotiveRunResult::scene)
      .def_readonly("reference_channel", &AutomotiveRunResult::reference_channel)
      .def_readonly("ego_speed", &AutomotiveRunResult::ego_speed);
}

void bindRunFunctions(py::module_& m) {
  m.def(
      "scanning_options",
      [](const ScanningSequence& sequence, const py::kwargs& kw) {
        return scanningKeywords(defaultScanningOptions(sequence), kw);
      },
      py::arg("sequence"),
      "The options run_scanning runs `sequence` with: the defaults for its radar (defaultScanningOptions), "
      "then the keywords.");
  m.def(
      "run_scanning",
      [](const std::filesystem::path& path_arg, const std::string& format, const py::kwargs& kw) {
        const std::string path = path_arg.string();
        const ScanFormat f = parseEnum<ScanFormat>(format);
        // The sequence is read with the keywords' reader settings, the run uses its radar's defaults.
        const auto seq_options =
            withKeywords(ScanningRunOptions{}, without(kw, {"method"}), "ScanningRunOptions", "method").sequence;
        ScanningRunOptions defaults;
        std::unique_ptr<ScanningSequence> sequence;
        {
          py::gil_scoped_release release;
          sequence = std::make_unique<ScanningSequence>(path, f, seq_options);
          defaults = defaultScanningOptions(*sequence);
        }
        const ScanningRunOptions o = scanningKeywords(defaults, kw);
        py::gil_scoped_release release;
        return runScanningOdometry(*sequence, o);
      },
      py::arg("path"), py::arg("format") = "oxford",
      "Runs the scanning odometry over a sequence directory as radar_odometry --format FORMAT --sequence PATH "
      "does: the defaults for its radar, then the keywords (method='pcl-ndt', threads=1, "
      "front_end={'threshold': 0.4}, matcher={'grid': 4.0}, ...: ScanningRunOptions fields). Returns a "
      "ScanningRun. The GIL is released while it runs.");
  m.def(
      "run_automotive",
      [](const std::filesystem::path& dataroot_arg, const std::string& scene, const std::string& version,
         const py::kwargs& kw) {
        const std::string dataroot = dataroot_arg.string();
        const std::string method = kw.contains("method") ? keywordAs<std::string>(kw["method"], "method") : "pw-ndt";
        AutomotiveRunOptions o =
            withKeywords(AutomotiveRunOptions{}, without(kw, {"method"}), "AutomotiveRunOptions", "method, version");
        o = withMethod(o, method);
        o.validate();
        py::gil_scoped_release release;
        const NuScenesDataset dataset(dataroot, version);
        return runAutomotiveOdometry(dataset, dataset.scene(scene), o);
      },
      py::arg("dataroot"), py::arg("scene"), py::arg("version") = "",
      "Runs the automotive odometry over one nuScenes scene as radar_odometry --format nuscenes --dataroot "
      "DATAROOT --scene SCENE does; keywords are AutomotiveRunOptions fields, and method='rapp-ndt' sets what "
      "it needs (with_method). Returns an AutomotiveRun. The GIL is released while it runs.");
}

/// run_rosbag: a ROS 1 bag through a sensor description (a build without ROS says so when called).
void bindRosbagRun(py::module_& m) {
  m.def(
      "run_rosbag",
      [](const std::filesystem::path& bag_arg, const std::string& sensors, const py::kwargs& kw) -> py::object {
#ifdef RADAR_NDT_WITH_ROS
        const std::string bag_path = bag_arg.string();
        const SensorDescription d = readSensorDescription(sensors);
        if (!d.radars.empty() && d.radars[0].kind == RadarKind::Scanning) {  // polar images: the scanning run
          const ScanningRunOptions o = scanningKeywords(ScanningRunOptions{}, kw);
          ScanningRunResult r;
          {
            py::gil_scoped_release release;
            const ros1::RosbagScanSequence bag(bag_path, d);
            r = runScanningOdometry(bag, o);
          }
          return py::cast(std::move(r));
        }
        const std::string method = kw.contains("method") ? keywordAs<std::string>(kw["method"], "method") : "pw-ndt";
        AutomotiveRunOptions o =
            withKeywords(AutomotiveRunOptions{}, without(kw, {"method"}), "AutomotiveRunOptions", "method");
        o = withMethod(o, method);
        o.validate();
        AutomotiveRunResult r;
        {
          py::gil_scoped_release release;
          const ros1::RosbagRadarSequence bag(bag_path, d);
          const auto car = bag.vehicleSignals();
          if (o.odometry.car.wheels && (!car || car->speed.empty()))
            throw std::invalid_argument("odometry.car.wheels: " + sensors + " names no speed topic");
          if (o.odometry.car.gyro && (!car || car->yaw_rate.empty()))
            throw std::invalid_argument("odometry.car.gyro: " + sensors + " names no imu topic");
          AutomotiveInputs inputs{bag, o.odometry.car.any() ? bag.vehicleSignals() : nullptr, bag.problems()};
          r = runAutomotiveOdometry(inputs, o, makeMatcher(o.matcher));
        }
        return py::cast(std::move(r));
#else
        (void)bag_arg;
        (void)sensors;
        (void)kw;
        throw std::runtime_error("run_rosbag: this build has no ROS support (Debian's ROS 1 was not found)");
#endif
      },
      py::arg("bag"), py::arg("sensors"),
      "Runs the odometry over a ROS 1 bag as radar_odometry --format rosbag --bag BAG --sensors SENSORS does "
      "(a sensor description file, or 'preset:NAME'). Point-cloud radars: the automotive odometry, keywords "
      "as run_automotive's, an AutomotiveRun; a scanning radar's polar images: the scanning odometry, "
      "keywords as run_scanning's, a ScanningRun. The GIL is released while it runs.");
}

void bindRuns(py::module_& m) {
  bindRunResults(m);
  bindRunFunctions(m);
  bindRosbagRun(m);
}

void bindEvaluation(py::module_& m) {
  m.def(
      "evaluate",
      [](const Trajectory& gt, const Trajectory& est, const std::string& metrics, const py::kwargs& kw) {
        const auto o = withKeywords(EvaluationOptions{}, kw, "evaluate");
        const EvaluationReport report = evaluate(associate(gt, est), parseMetrics(metrics), o);
        py::dict d = jsonToPython(toJson(report))["metrics"].cast<py::dict>();
        d["associated_poses"] = report.associated_poses;
        return d;
      },
      py::arg("ground_truth"), py::arg("estimate"), py::arg("metrics") = "all",
      "The metrics (docs/metrics.md: 'kitti', '1m', 'frame', 'ate', 'all' or a comma-separated list) of an "
      "estimate against ground truth, as radar_eval --json gives them (undefined errors are None). Poses are "
      "associated by time when both have stamps, else by index. Keywords: EvaluationOptions.");
  auto segment = [](const SegmentError& e) {
    py::dict d;
    d["trans_err_pct"] = e.trans_err_pct;
    d["rot_err_deg_per_m"] = e.rot_err_deg_per_m;
    d["segments"] = e.segments;
    return d;
  };
  m.def(
      "kitti_error",
      [segment](const Trajectory& gt, const Trajectory& est, const std::vector<double>& lengths, std::size_t step) {
        return segment(kittiError(associate(gt, est), lengths, step));
      },
      py::arg("ground_truth"), py::arg("estimate"),
      py::arg("lengths") = std::vector<double>{100, 200, 300, 400, 500, 600, 700, 800}, py::arg("step") = 10,
      "KITTI's segment error: {trans_err_pct, rot_err_deg_per_m, segments} (NaN without segments).");
  m.def(
      "one_meter_error",
      [segment](const Trajectory& gt, const Trajectory& est, double length) {
        return segment(oneMeterError(associate(gt, est), length));
      },
      py::arg("ground_truth"), py::arg("estimate"), py::arg("length") = 1.0, "The paper's nuScenes 1 m metric.");
  m.def(
      "frame_error",
      [](const Trajectory& gt, const Trajectory& est, std::size_t step) {
        const FrameError e = frameError(associate(gt, est), step);
        py::dict d;
        d["trans_err_m"] = e.trans_err_m;
        d["rot_err_deg"] = e.rot_err_deg;
        d["pairs"] = e.pairs;
        return d;
      },
      py::arg("ground_truth"), py::arg("estimate"), py::arg("step") = 1,
      "Mean relative pose error per frame: {trans_err_m, rot_err_deg, pairs}.");
  m.def(
      "absolute_trajectory_error",
      [](const Trajectory& gt, const Trajectory& est) {
        const AbsoluteError e = absoluteTrajectoryError(associate(gt, est));
        py::dict d;
        d["rmse_m"] = e.rmse_m;
        d["poses"] = e.poses;
        d["alignment"] = Eigen::Vector3d(e.alignment);
        return d;
      },
      py::arg("ground_truth"), py::arg("estimate"),
      "ATE: RMSE of the x-y positions after the SE(2) alignment: {rmse_m, poses, alignment (x, y, yaw)}.");
}

}  // namespace python
}  // namespace radar_ndt

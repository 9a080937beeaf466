// Whole runs as radar_odometry runs them (the same defaults for the sequence's radar, the same
// pipelines), and the metrics on trajectories.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>  // paths as str or os.PathLike

#include "bindings.h"
#include "keywords.h"
#include "radar_ndt/evaluation/report.h"
#include "radar_ndt/evaluation/run_report.h"
#include "radar_ndt/io/dataset_format.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/odometry_run.h"
#include "radar_ndt/pipeline/scanning_run.h"
#ifdef RADAR_NDT_WITH_ROS
#include "radar_ndt/ros/bag_reader.h"
#endif

namespace radar_ndt {
namespace python {

namespace {

py::object jsonToPython(const std::string& text) {
  return py::module_::import("json").attr("loads")(text);
}

/// The run's summary as radar_odometry --json gives it: summaryJson, and when `metrics` names any
/// ("default": the pipeline's) and the run has ground truth, the metrics with the method's own
/// prior beside them (evaluateRun: the library's one summary).
template <typename Result>
py::dict summaryOf(const Result& r, const std::string& metrics) {
  if (metrics.empty() || r.ground_truth.empty()) return py::reinterpret_borrow<py::dict>(jsonToPython(summaryJson(r)));
  const RunEvaluation e = evaluateRun(r, metrics == "default" ? std::vector<Metric>{} : parseMetrics(metrics));
  return py::reinterpret_borrow<py::dict>(jsonToPython(summaryJson(r, e)));
}

/// The run `source` and `kw` ask for, through the library's one entry (OdometryRun), opened
/// without the GIL.
std::unique_ptr<OdometryRun> openSource(const RunSource& source, const py::kwargs& kw) {
  const Settings given = settingsFromKeywords(kw);
  py::gil_scoped_release release;
  return std::make_unique<OdometryRun>(source, given);
}

/// The run to its end without the GIL.
AutomotiveRunResult runAutomotive(const OdometryRun& run) {
  py::gil_scoped_release release;
  return run.runAutomotive();
}
ScanningRunResult runScanning(const OdometryRun& run) {
  py::gil_scoped_release release;
  return run.runScanning();
}
InertialRunResult runInertial(const OdometryRun& run) {
  py::gil_scoped_release release;
  return run.runInertial();
}

/// A {path: value} dict of every field (what radar_odometry --show-options prints).
template <typename R>
py::dict valuesOf(const R& options) {
  std::function<py::object(const FieldValue&)> conv = [&conv](const FieldValue& v) -> py::object {
    switch (v.kind()) {
      case FieldValue::Kind::Bool: return py::bool_(v.boolean());
      case FieldValue::Kind::Integer: return py::int_(v.integer());
      case FieldValue::Kind::Real: return py::float_(v.real());
      case FieldValue::Kind::Text: return py::str(v.text());
      default: {
        py::list items;
        for (const FieldValue& item : v.list()) items.append(conv(item));
        return std::move(items);
      }
    }
  };
  py::dict out;
  for (const auto& [path, value] : fieldValues(options)) out[py::str(path)] = conv(value);
  return out;
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

/// The 6-DoF run's result (inertial_run.h).
void bindInertialRun(py::module_& m) {
  py::class_<InertialRunResult>(m, "InertialRun", "What run_rosbag returns for a 6-DoF method.")
      .def_readonly("sequence", &InertialRunResult::sequence)
      .def_readonly("method", &InertialRunResult::method)
      .def_readonly("imu", &InertialRunResult::imu, "whether the IMU was fused")
      .def_readonly("radar", &InertialRunResult::radar, "the radar that ran")
      .def_readonly("prior", &InertialRunResult::prior, "what each match started from")
      .def_readonly("period", &InertialRunResult::period_s)
      .def_readonly("estimate", &InertialRunResult::estimate, "the estimated 6-DoF Trajectory (stamps in s)")
      .def_readonly("ground_truth", &InertialRunResult::ground_truth, "the recording's, at the scans; may be empty")
      .def_readonly("problems", &InertialRunResult::problems)
      .def_readonly("scans", &InertialRunResult::scans)
      .def_readonly("matched", &InertialRunResult::matched)
      .def_readonly("fallbacks", &InertialRunResult::fallbacks)
      .def_readonly("still", &InertialRunResult::still)
      .def_readonly("seconds", &InertialRunResult::seconds)
      .def_property_readonly(
          "stamps", [](const InertialRunResult& r) { return stampsArray(r.estimate); },
          "numpy.ndarray: (N,) estimate stamps (s)")
      .def_property_readonly(
          "poses", [](const InertialRunResult& r) { return posesArray(r.estimate); },
          "numpy.ndarray: (N, 4, 4) estimated poses")
      .def(
          "summary", [](const InertialRunResult& r, const std::string& metrics) { return summaryOf(r, metrics); },
          py::arg("metrics") = "",
          "The run summary as radar_odometry --json gives it, as a dict; metrics ('default': ate6, re, final) "
          "adds them against the ground truth, as --eval does.")
      .def(
          "steps_csv", [](const InertialRunResult& r) { return stepsCsv(r); },
          "The per-scan CSV radar_odometry --steps writes, as text.");
}

void bindRunResults(py::module_& m) {
  bindInertialRun(m);
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

/// The field table of R, each field as a dict (what option_fields returns).
template <typename R>
py::list fieldsOf() {
  auto kind = [](FieldValue::Kind k) {
    switch (k) {
      case FieldValue::Kind::Bool: return "bool";
      case FieldValue::Kind::Integer: return "int";
      case FieldValue::Kind::Real: return "float";
      case FieldValue::Kind::Text: return "str";
      default: return "list";
    }
  };
  py::list out;
  for (const FieldEntry<R>& e : fieldEntries<R>()) {
    py::dict d;
    d["path"] = e.path;
    d["kind"] = kind(e.kind);
    if (e.kind == FieldValue::Kind::List) d["item_kind"] = kind(e.item_kind);
    d["help"] = std::string(e.field.help);
    d["unit"] = std::string(e.field.unit_text);
    d["low"] = e.field.bounds.lo;
    d["high"] = e.field.bounds.hi;
    d["low_open"] = e.field.bounds.lo_open;
    d["high_open"] = e.field.bounds.hi_open;
    d["names"] = e.names;
    d["layout"] = e.scope;
    d["option"] = e.field.cli_name ? py::object(py::str(e.field.cli_name)) : py::none();
    d["switch_sets"] = e.field.off_switch_help ? py::object(py::bool_(e.field.switch_sets)) : py::none();
    d["spelled"] = e.field.true_name ? py::object(py::make_tuple(e.field.false_name, e.field.true_name)) : py::none();
    out.append(d);
  }
  return out;
}

/// The options a run takes and their table: scanning_options, run_options, option_values,
/// option_fields.
void bindRunOptions(py::module_& m) {
  m.def(
      "option_fields",
      [](const std::string& pipeline) {
        if (pipeline == "automotive") return fieldsOf<AutomotiveRunOptions>();
        if (pipeline == "scanning") return fieldsOf<ScanningRunOptions>();
        if (pipeline == "6dof") return fieldsOf<InertialRunOptions>();
        throw std::invalid_argument("option_fields: 'automotive', 'scanning' or '6dof', not '" + pipeline + "'");
      },
      py::arg("pipeline"),
      "The run options' field table of a pipeline ('automotive', 'scanning' or '6dof'): for each field its path (the "
      "keyword's, nested dicts for the dots), kind (bool, int, float, str, list), help, unit, bounds (low, high, "
      "low_open, high_open), an enumeration's names, the dataset layout it applies to alone, the command line's "
      "option (switch_sets: what its switch sets; spelled: a flag's two names), as radar_odometry --list-options "
      "lists them.");
  m.def(
      "scanning_options",
      [](const ScanningSequence& sequence, const py::kwargs& kw) {
        return scanningRunOptions(settingsFromKeywords(kw), sequence.formatName(), defaultScanningOptions(sequence));
      },
      py::arg("sequence"),
      "The options run_scanning runs `sequence` with: the defaults for its radar (defaultScanningOptions), "
      "then the keywords.");
  m.def(
      "run_options",
      [](const std::string& format, const py::kwargs& kw) -> py::object {
        const Settings given = settingsFromKeywords(kw);
        if (format == "rosbag")
          throw std::invalid_argument(
              "run_options: a recording's pipeline is its description's: give nuscenes or "
              "a scanning layout");
        if (pipelineOf(RunSource{format, "", "", "", ""}) == PipelineKind::Automotive)
          return py::cast(automotiveRunOptions(given));
        return py::cast(scanningRunOptions(given, format));
      },
      py::arg("format"),
      "The options a run of `format` (nuscenes, oxford, radiate, boreas) takes from the keywords, over the "
      "library's defaults (a Boreas sequence with chirp types has its own: scanning_options): an "
      "AutomotiveRunOptions or a ScanningRunOptions, as radar_odometry --format FORMAT --show-options gives them.");
  m.def(
      "option_values", [](const AutomotiveRunOptions& o) { return valuesOf(o); }, py::arg("options"),
      "Every field of the options by its path, {path: value}: what radar_odometry --show-options prints.");
  m.def(
      "option_values", [](const ScanningRunOptions& o) { return valuesOf(o); }, py::arg("options"));
}

void bindRunFunctions(py::module_& m) {
  m.def(
      "run_scanning",
      [](const std::filesystem::path& path, const std::string& format, const py::kwargs& kw) {
        if (!isScanLayout(parseEnum<DatasetFormat>(format)))
          throw std::invalid_argument("format '" + format + "' is not a scanning layout (oxford, radiate, boreas)");
        return runScanning(*openSource(RunSource{format, path.string(), "", "", ""}, kw));
      },
      py::arg("path"), py::arg("format") = "oxford",
      "Runs the scanning odometry over a sequence directory as radar_odometry --format FORMAT --sequence PATH "
      "does: the defaults for its radar, then the keywords (method='pcl-ndt', threads=1, "
      "front_end={'threshold': 0.4}, matcher={'grid': 4.0}, ...: ScanningRunOptions fields). Returns a "
      "ScanningRun. The GIL is released while it runs.");
  m.def(
      "run_automotive",
      [](const std::filesystem::path& dataroot, const std::string& scene, const std::string& version,
         const py::kwargs& kw) {
        return runAutomotive(*openSource(RunSource{"nuscenes", dataroot.string(), scene, version, ""}, kw));
      },
      py::arg("dataroot"), py::arg("scene"), py::arg("version") = "",
      "Runs the automotive odometry over one nuScenes scene as radar_odometry --format nuscenes --dataroot "
      "DATAROOT --scene SCENE does; keywords are AutomotiveRunOptions fields, and method='rapp-ndt' sets what "
      "it needs (with_method). Returns an AutomotiveRun. The GIL is released while it runs.");
}

/// run_rosbag: a ROS 1 bag through a sensor description (a build without ROS says so when called).
void bindRosbagRun(py::module_& m) {
#ifdef RADAR_NDT_WITH_ROS
  ros1::registerBagReader();
#endif
  m.def(
      "run_rosbag",
      [](const std::filesystem::path& bag, const std::string& sensors, const py::kwargs& kw) -> py::object {
        const auto run = openSource(RunSource{"rosbag", bag.string(), "", "", sensors}, kw);
        if (run->pipeline() == PipelineKind::Automotive) return py::cast(runAutomotive(*run));
        if (run->pipeline() == PipelineKind::Inertial) return py::cast(runInertial(*run));
        return py::cast(runScanning(*run));
      },
      py::arg("bag"), py::arg("sensors"),
      "Runs the odometry over a ROS 1 bag as radar_odometry --format rosbag --bag BAG --sensors SENSORS does "
      "(a sensor description file, or 'preset:NAME'). Point-cloud radars: the automotive odometry, keywords "
      "as run_automotive's (sequence={'channels': [...], 'reference_channel': ..., 'filter': {'max_range': ...}} "
      "choose the radars), an AutomotiveRun; a 4D radar's with a 6-DoF method (matcher={'method': 'pw-ndt-3d'}, "
      "'pcl-ndt-3d', 'pcl-gicp' or 'doppler-imu'; imu=True fuses the rig's IMU; InertialRunOptions fields), the "
      "6-DoF odometry, an InertialRun; a scanning radar's polar images: the scanning odometry, keywords "
      "as run_scanning's, a ScanningRun. The GIL is released while it runs.");
}

void bindRuns(py::module_& m) {
  bindRunResults(m);
  bindRunOptions(m);
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
      "The metrics (docs/metrics.md: 'kitti', '1m', 'frame', 'ate', 'ate6', 're', 'final', 'all' or a list) of an "
      "estimate against ground truth, as radar_eval --json gives them (undefined errors are None; 'all' adds the "
      "6-DoF ones for 6-DoF trajectories). Keywords: EvaluationOptions.");
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

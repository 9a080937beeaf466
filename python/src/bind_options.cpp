// The options structs as Python classes, made from their field tables (radar_ndt/fields.h): every
// field an attribute of the same name, documented by its table (help, unit, range); enumerations
// are strings, the names their name tables give ("overlapping-grids", "joint", ...). radar_ndt's
// keyword arguments are applied onto these (keywords.h), so a field added to a table is a
// Python attribute and keyword with nothing written here; test_options.py checks every field of
// the headers is reachable. The registry of matchers is radar_ndt.matchers().

#include <deque>

#include <pybind11/stl.h>

#include "bindings.h"
#include "radar_ndt/evaluation/report.h"
#include "radar_ndt/odometry/matcher_registry.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/scanning_run.h"

namespace radar_ndt {
namespace python {

namespace {

template <typename T, typename = void>
struct HasValidate : std::false_type {};
template <typename T>
struct HasValidate<T, std::void_t<decltype(std::declval<const T&>().validate())>> : std::true_type {};

/// A field's docstring: its help, unit, range and, for an enumeration, its names.
template <typename M>
const char* fieldDoc(const Field& f) {
  static std::deque<std::string> docs;  // the docstrings live as long as the module
  std::string doc = f.help;
  if (*f.unit_text) doc += " (" + std::string(f.unit_text) + ")";
  if constexpr (std::is_arithmetic_v<M> && !std::is_same_v<M, bool>)
    if (f.bounds.text() != "finite") doc += "; " + f.bounds.text();
  if constexpr (std::is_enum_v<M>) doc += ": " + enumChoices<M>(" | ");
  if (f.choices_text) doc += ": " + f.choices_text();
  docs.push_back(doc);
  return docs.back().c_str();
}

/// radar_ndt::`name` as a Python class: every field of its table an attribute.
template <typename T>
void bindOptions(py::module_& m, const char* name, const char* header) {
  py::class_<T> c(m, name,
                  (std::string("radar_ndt::") + name + " (" + header +
                   "): every field an attribute; keyword arguments of the functions that take it set them.")
                      .c_str());
  c.def(py::init<>());
  c.def("__copy__", [](const T& o) { return T(o); });
  c.def("__deepcopy__", [](const T& o, const py::dict&) { return T(o); });
  if constexpr (HasValidate<T>::value)
    c.def("validate", &T::validate, "Raises ValueError naming the first setting out of range.");
  T::fields([&](auto member, const Field& f) {
    using M = std::remove_reference_t<decltype(std::declval<T&>().*member)>;
    if constexpr (std::is_enum_v<M>)
      c.def_property(
          f.name, [member](const T& o) { return std::string(toString(o.*member)); },
          [member, name = std::string(f.name)](T& o, const std::string& v) {
            try {
              o.*member = parseEnum<M>(v);
            } catch (const std::invalid_argument& e) {
              throw std::invalid_argument(name + ": " + e.what());
            }
          },
          fieldDoc<M>(f));
    else
      c.def_readwrite(f.name, member, fieldDoc<M>(f));
  });
}

void bindMatcherOptions(py::module_& m) {
  bindOptions<WeightedNDT2DSettings>(m, "WeightedNDT2DSettings", "radar_ndt/registration/weighted_ndt_2d_settings.h");
  bindOptions<MatcherOptions>(m, "MatcherOptions", "radar_ndt/odometry/matcher.h");
  m.def(
      "matchers",
      [] {
        py::list out;
        for (const std::string& name : matcherNames()) {
          const MatcherEntry& e = findMatcher(name);
          py::dict d;
          d["name"] = e.name;
          d["help"] = e.help;
          d["power_weights"] = e.uses.power_weights;
          d["doppler_weights"] = e.uses.doppler_weights;
          d["needs_doppler"] = e.uses.needs_doppler;
          d["sweep_times"] = e.uses.sweep_times;
          d["merges_source"] = e.uses.merges_source;
          d["three_d"] = e.uses.three_d;
          out.append(d);
        }
        return out;
      },
      "The registry of matchers, in its order: for each, its name (method=...), what it is and what it uses of "
      "the points (power_weights, doppler_weights, needs_doppler, sweep_times, merges_source, three_d).");
}

void bindScanningOptions(py::module_& m) {
  bindOptions<PolarConvention>(m, "PolarConvention", "radar_ndt/io/polar_scan.h");
  bindOptions<OxfordPolarOptions>(m, "OxfordPolarOptions", "radar_ndt/io/oxford_scan.h");
  bindOptions<RadiatePolarOptions>(m, "RadiatePolarOptions", "radar_ndt/io/radiate_scan.h");
  bindOptions<BoreasPolarOptions>(m, "BoreasPolarOptions", "radar_ndt/io/boreas_scan.h");
  bindOptions<ScanningSequenceOptions>(m, "ScanningSequenceOptions", "radar_ndt/io/scanning_sequence.h");
  bindOptions<PowerThresholdOptions>(m, "PowerThresholdOptions", "radar_ndt/frontend/power_threshold.h");
  bindOptions<ChirpCorrectionOptions>(m, "ChirpCorrectionOptions", "radar_ndt/frontend/chirp_correction.h");
  bindOptions<ScanningMotionGateOptions>(m, "ScanningMotionGateOptions", "radar_ndt/odometry/motion_gate.h");
  bindOptions<MotionCompensationOptions>(m, "MotionCompensationOptions", "radar_ndt/odometry/motion_compensation.h");
  bindOptions<KeyframeOptions>(m, "KeyframeOptions", "radar_ndt/odometry/keyframe_policy.h");
  bindOptions<FitCheckOptions>(m, "FitCheckOptions", "radar_ndt/odometry/fit_history.h");
  bindOptions<GyroOptions>(m, "GyroOptions", "radar_ndt/odometry/gyro_yaw.h");
  bindOptions<ScanningOdometryOptions>(m, "ScanningOdometryOptions", "radar_ndt/odometry/scanning_odometry.h");
  bindOptions<ScanningRunOptions>(m, "ScanningRunOptions", "radar_ndt/pipeline/scanning_run.h");
}

void bindAutomotiveOptions(py::module_& m) {
  bindOptions<NuScenesRadarFilter>(m, "NuScenesRadarFilter", "radar_ndt/io/nuscenes.h");
  bindOptions<NuScenesSequenceOptions>(m, "NuScenesSequenceOptions", "radar_ndt/io/nuscenes_sequence.h");
  bindOptions<PolarAccuracy>(m, "PolarAccuracy", "radar_ndt/frontend/point_covariance.h");
  bindOptions<EgoVelocityOptions>(m, "EgoVelocityOptions", "radar_ndt/frontend/ego_velocity.h");
  bindOptions<AutomotiveFrontEndOptions>(m, "AutomotiveFrontEndOptions", "radar_ndt/frontend/automotive_front_end.h");
  bindOptions<MotionFusionOptions>(m, "MotionFusionOptions", "radar_ndt/odometry/motion_fusion.h");
  bindOptions<CarSensorOptions>(m, "CarSensorOptions", "radar_ndt/odometry/car_fusion.h");
  bindOptions<AutomotiveMotionGateOptions>(m, "AutomotiveMotionGateOptions", "radar_ndt/odometry/motion_gate.h");
  bindOptions<AutomotiveOdometryOptions>(m, "AutomotiveOdometryOptions", "radar_ndt/odometry/automotive_odometry.h");
  py::class_<AutomotiveOdometryOptions>(m.attr("AutomotiveOdometryOptions"))
      .def("paper", &AutomotiveOdometryOptions::paper, py::arg("n"),
           "These options in the paper's configuration: submap-to-submap with N = n, no fusion.");
  bindOptions<AutomotiveRunOptions>(m, "AutomotiveRunOptions", "radar_ndt/pipeline/automotive_run.h");
  bindOptions<EvaluationOptions>(m, "EvaluationOptions", "radar_ndt/evaluation/report.h");
}

}  // namespace

void bindOptions(py::module_& m) {
  bindMatcherOptions(m);
  bindScanningOptions(m);
  bindAutomotiveOptions(m);
  m.def(
      "with_method", [](const AutomotiveRunOptions& o, const std::string& method) { return withMethod(o, method); },
      py::arg("options"), py::arg("method"),
      "The automotive run options set for `method` and what it needs beyond it (a matcher with Doppler "
      "weights, rapp-ndt: Doppler weights, moving detections kept), as radar_odometry --method sets them.");
}

}  // namespace python
}  // namespace radar_ndt

// The options structs as Python classes, every field an attribute of the same name (the C++
// header's comment documents each). radar_ndt's keyword arguments are applied onto these
// (python/radar_ndt/_options.py), so a new field only needs its line here; the test
// test_options.py checks every field of the headers is reachable. Enumerations are strings, the
// names the command-line apps take ("pw-ndt", "overlapping-grids", ...).

#include <pybind11/stl.h>

#include "bindings.h"
#include "radar_ndt/evaluation/report.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/scanning_run.h"

namespace radar_ndt {
namespace python {

namespace {

template <typename T, typename = void>
struct HasValidate : std::false_type {};
template <typename T>
struct HasValidate<T, std::void_t<decltype(std::declval<const T&>().validate())>> : std::true_type {};

template <typename T>
py::class_<T> optionsClass(py::module_& m, const char* name, const char* header) {
  py::class_<T> c(m, name,
                  (std::string("radar_ndt::") + name + " (" + header +
                   "): every field an attribute; keyword arguments of the functions that take it set them.")
                      .c_str());
  c.def(py::init<>());
  c.def("__copy__", [](const T& o) { return T(o); });
  c.def("__deepcopy__", [](const T& o, const py::dict&) { return T(o); });
  if constexpr (HasValidate<T>::value)
    c.def("validate", &T::validate, "Raises ValueError naming the first setting out of range.");
  return c;
}

/// An enumeration field as its name (the apps' spelling), parsed back on assignment.
template <typename C, typename E>
void enumField(py::class_<C>& c, const char* name, E C::*field, E (*parse)(const std::string&), const char* (*str)(E)) {
  c.def_property(
      name, [field, str](const C& o) { return std::string(str(o.*field)); },
      [field, parse](C& o, const std::string& v) { o.*field = parse(v); });
}

CellLookup parseCellLookup(const std::string& s) {
  if (s == "neighbours") return CellLookup::Neighbours;
  if (s == "overlapping-grids") return CellLookup::OverlappingGrids;
  throw std::invalid_argument("cell_lookup must be neighbours or overlapping-grids, not '" + s + "'");
}
const char* cellLookupName(CellLookup c) {
  return c == CellLookup::Neighbours ? "neighbours" : "overlapping-grids";
}

BoreasFlag parseBoreasFlag(const std::string& s) {
  if (s == "auto") return BoreasFlag::Auto;
  if (s == "validity") return BoreasFlag::Validity;
  if (s == "chirp-type") return BoreasFlag::ChirpType;
  throw std::invalid_argument("flag must be auto, validity or chirp-type, not '" + s + "'");
}
const char* boreasFlagName(BoreasFlag f) {
  return f == BoreasFlag::Auto ? "auto" : f == BoreasFlag::Validity ? "validity" : "chirp-type";
}

const char* methodName(Method m) {
  return toString(m);
}
const char* modeName(AutomotiveMatchMode m) {
  return toString(m);
}
const char* covarianceName(PointCovarianceModel m) {
  return toString(m);
}
const char* egoModelName(EgoVelocityModel m) {
  return toString(m);
}
const char* compensationName(CompensationMode m) {
  return toString(m);
}

void bindMatcherOptions(py::module_& m) {
  {
    using T = WeightedNDT2DSettings;
    auto c = optionsClass<T>(m, "WeightedNDT2DSettings", "radar_ndt/registration/weighted_ndt_2d_settings.h");
    c.def_readwrite("resolutions", &T::resolutions)
        .def_readwrite("power_shift", &T::power_shift)
        .def_readwrite("shift_source_weights", &T::shift_source_weights)
        .def_readwrite("eigenvalue_ratio", &T::eigenvalue_ratio)
        .def_readwrite("min_points_per_cell", &T::min_points_per_cell)
        .def_readwrite("source_voxel_size", &T::source_voxel_size)
        .def_readwrite("max_step_translation", &T::max_step_translation)
        .def_readwrite("max_step_rotation", &T::max_step_rotation)
        .def_readwrite("coarse_subsample", &T::coarse_subsample)
        .def_readwrite("coarse_min_points", &T::coarse_min_points)
        .def_readwrite("coarse_transformation_epsilon", &T::coarse_transformation_epsilon)
        .def_readwrite("coarse_rotation_epsilon", &T::coarse_rotation_epsilon)
        .def_readwrite("stationary_translation_ratio", &T::stationary_translation_ratio)
        .def_readwrite("stationary_rotation", &T::stationary_rotation)
        .def_readwrite("armijo", &T::armijo)
        .def_readwrite("max_halvings", &T::max_halvings)
        .def_readwrite("eigenvalue_floor", &T::eigenvalue_floor)
        .def_readwrite("negligible_decrease", &T::negligible_decrease)
        .def_readwrite("min_matched_points", &T::min_matched_points)
        .def_readwrite("min_information_ratio", &T::min_information_ratio);
    enumField(c, "cell_lookup", &T::cell_lookup, &parseCellLookup, &cellLookupName);
  }
  {
    using T = MatcherOptions;
    auto c = optionsClass<T>(m, "MatcherOptions", "radar_ndt/odometry/matcher.h");
    c.def_readwrite("ours", &T::ours)
        .def_readwrite("ours_max_iterations", &T::ours_max_iterations)
        .def_readwrite("icp_max_iterations", &T::icp_max_iterations)
        .def_readwrite("icp_transformation_epsilon", &T::icp_transformation_epsilon)
        .def_readwrite("icp_fitness_epsilon", &T::icp_fitness_epsilon);
    enumField(c, "method", &T::method, &parseMethod, &methodName);
  }
}

void bindScanningOptions(py::module_& m) {
  {
    using T = PolarConvention;
    optionsClass<T>(m, "PolarConvention", "radar_ndt/io/polar_scan.h")
        .def_readwrite("range_resolution", &T::range_resolution)
        .def_readwrite("range_offset_bins", &T::range_offset_bins)
        .def_readwrite("azimuth_zero", &T::azimuth_zero)
        .def_readwrite("clockwise", &T::clockwise);
  }
  {
    using T = OxfordPolarOptions;
    optionsClass<T>(m, "OxfordPolarOptions", "radar_ndt/io/oxford_scan.h")
        .def_readwrite("convention", &T::convention)
        .def_readwrite("encoder_size", &T::encoder_size)
        .def_readwrite("expected_bins", &T::expected_bins);
  }
  {
    using T = RadiatePolarOptions;
    optionsClass<T>(m, "RadiatePolarOptions", "radar_ndt/io/radiate_scan.h")
        .def_readwrite("convention", &T::convention)
        .def_readwrite("expected_azimuths", &T::expected_azimuths)
        .def_readwrite("sweep_period", &T::sweep_period);
  }
  {
    using T = BoreasPolarOptions;
    auto c = optionsClass<T>(m, "BoreasPolarOptions", "radar_ndt/io/boreas_scan.h");
    c.def_readwrite("range_resolution", &T::range_resolution)
        .def_readwrite("range_offset_bins", &T::range_offset_bins)
        .def_readwrite("zero_below", &T::zero_below)
        .def_readwrite("encoder_size", &T::encoder_size)
        .def_readwrite("expected_bins", &T::expected_bins);
    enumField(c, "flag", &T::flag, &parseBoreasFlag, &boreasFlagName);
  }
  {
    using T = ScanningSequenceOptions;
    optionsClass<T>(m, "ScanningSequenceOptions", "radar_ndt/io/scanning_sequence.h")
        .def_readwrite("oxford", &T::oxford)
        .def_readwrite("radiate", &T::radiate)
        .def_readwrite("boreas", &T::boreas);
  }
  {
    using T = PowerThresholdOptions;
    optionsClass<T>(m, "PowerThresholdOptions", "radar_ndt/frontend/power_threshold.h")
        .def_readwrite("cartesian", &T::cartesian)
        .def_readwrite("cartesian_resolution", &T::cartesian_resolution)
        .def_readwrite("max_range", &T::max_range)
        .def_readwrite("min_range", &T::min_range)
        .def_readwrite("threshold", &T::threshold)
        .def_readwrite("beam_width_deg", &T::beam_width_deg);
  }
  {
    using T = ChirpCorrectionOptions;
    optionsClass<T>(m, "ChirpCorrectionOptions", "radar_ndt/frontend/chirp_correction.h")
        .def_readwrite("enabled", &T::enabled)
        .def_readwrite("max_shift", &T::max_shift)
        .def_readwrite("min_range", &T::min_range)
        .def_readwrite("max_range", &T::max_range)
        .def_readwrite("top_share", &T::top_share)
        .def_readwrite("min_pairs", &T::min_pairs)
        .def_readwrite("min_peak", &T::min_peak);
  }
  {
    using T = ScanningMotionGateOptions;
    optionsClass<T>(m, "ScanningMotionGateOptions", "radar_ndt/odometry/motion_gate.h")
        .def_readwrite("enabled", &T::enabled)
        .def_readwrite("max_acceleration", &T::max_acceleration)
        .def_readwrite("max_yaw_acceleration", &T::max_yaw_acceleration)
        .def_readwrite("match_sigma_xy", &T::match_sigma_xy)
        .def_readwrite("match_sigma_yaw", &T::match_sigma_yaw);
  }
  {
    using T = MotionCompensationOptions;
    auto c = optionsClass<T>(m, "MotionCompensationOptions", "radar_ndt/odometry/motion_compensation.h");
    c.def_readwrite("enabled", &T::enabled)
        .def_readwrite("max_rounds", &T::max_rounds)
        .def_readwrite("tolerance", &T::tolerance);
    enumField(c, "mode", &T::mode, parseCompensationMode, compensationName);
  }
  {
    using T = KeyframeOptions;
    optionsClass<T>(m, "KeyframeOptions", "radar_ndt/odometry/keyframe_policy.h")
        .def_readwrite("distance", &T::distance)
        .def_readwrite("rotation", &T::rotation);
  }
  {
    using T = FitCheckOptions;
    optionsClass<T>(m, "FitCheckOptions", "radar_ndt/odometry/fit_history.h")
        .def_readwrite("min_relative_fit", &T::min_relative_fit)
        .def_readwrite("history", &T::history);
  }
  {
    using T = ScanningOdometryOptions;
    optionsClass<T>(m, "ScanningOdometryOptions", "radar_ndt/odometry/scanning_odometry.h")
        .def_readwrite("grid", &T::grid)
        .def_readwrite("grid_step", &T::grid_step)
        .def_readwrite("max_grid", &T::max_grid)
        .def_readwrite("power_shift", &T::power_shift)
        .def_readwrite("shift_source_weights", &T::shift_source_weights)
        .def_readwrite("max_shift_halvings", &T::max_shift_halvings)
        .def_readwrite("slow_speed", &T::slow_speed)
        .def_readwrite("slow_grid", &T::slow_grid)
        .def_readwrite("gate", &T::gate)
        .def_readwrite("compensation", &T::compensation)
        .def_readwrite("min_points", &T::min_points)
        .def_readwrite("start_hypotheses", &T::start_hypotheses)
        .def_readwrite("keyframes", &T::keyframes)
        .def_readwrite("fit", &T::fit);
  }
  {
    using T = ScanningRunOptions;
    optionsClass<T>(m, "ScanningRunOptions", "radar_ndt/pipeline/scanning_run.h")
        .def_readwrite("matcher", &T::matcher)
        .def_readwrite("sequence", &T::sequence)
        .def_readwrite("front_end", &T::front_end)
        .def_readwrite("chirp", &T::chirp)
        .def_readwrite("odometry", &T::odometry)
        .def_readwrite("start", &T::start)
        .def_readwrite("max_scans", &T::max_scans)
        .def_readwrite("threads", &T::threads)
        .def_readwrite("pcl_voxel_size", &T::pcl_voxel_size);
  }
}

void bindAutomotiveOptions(py::module_& m) {
  {
    using T = NuScenesRadarFilter;
    optionsClass<T>(m, "NuScenesRadarFilter", "radar_ndt/io/nuscenes.h")
        .def_readwrite("max_range", &T::max_range)
        .def_readwrite("invalid_states", &T::invalid_states)
        .def_readwrite("dyn_props", &T::dyn_props)
        .def_readwrite("ambig_states", &T::ambig_states);
  }
  {
    using T = NuScenesSequenceOptions;
    optionsClass<T>(m, "NuScenesSequenceOptions", "radar_ndt/io/nuscenes_sequence.h")
        .def_readwrite("filter", &T::filter)
        .def_readwrite("reference_channel", &T::reference_channel)
        .def_readwrite("channels", &T::channels);
  }
  {
    using T = PolarAccuracy;
    optionsClass<T>(m, "PolarAccuracy", "radar_ndt/frontend/point_covariance.h")
        .def_readwrite("range_sigma_near", &T::range_sigma_near)
        .def_readwrite("range_sigma_far", &T::range_sigma_far)
        .def_readwrite("near_range", &T::near_range)
        .def_readwrite("azimuth_sigma_center_deg", &T::azimuth_sigma_center_deg)
        .def_readwrite("azimuth_sigma_edge_deg", &T::azimuth_sigma_edge_deg)
        .def_readwrite("edge_azimuth_deg", &T::edge_azimuth_deg);
  }
  {
    using T = EgoVelocityOptions;
    auto c = optionsClass<T>(m, "EgoVelocityOptions", "radar_ndt/frontend/ego_velocity.h");
    c.def_readwrite("inlier_threshold", &T::inlier_threshold)
        .def_readwrite("max_iterations", &T::max_iterations)
        .def_readwrite("min_inliers", &T::min_inliers)
        .def_readwrite("min_inlier_ratio", &T::min_inlier_ratio)
        .def_readwrite("seed", &T::seed)
        .def_readwrite("lateral_sigma", &T::lateral_sigma);
    enumField(c, "model", &T::model, &parseEgoVelocityModel, &egoModelName);
  }
  {
    using T = AutomotiveFrontEndOptions;
    auto c = optionsClass<T>(m, "AutomotiveFrontEndOptions", "radar_ndt/frontend/automotive_front_end.h");
    c.def_readwrite("polar", &T::polar)
        .def_readwrite("ego_velocity", &T::ego_velocity)
        .def_readwrite("remove_moving", &T::remove_moving)
        .def_readwrite("compensate_time", &T::compensate_time);
    enumField(c, "covariance_model", &T::covariance_model, &parsePointCovarianceModel, &covarianceName);
  }
  {
    using T = MotionFusionOptions;
    optionsClass<T>(m, "MotionFusionOptions", "radar_ndt/odometry/motion_fusion.h")
        .def_readwrite("doppler_sigma_x", &T::doppler_sigma_x)
        .def_readwrite("doppler_sigma_y", &T::doppler_sigma_y)
        .def_readwrite("doppler_sigma_yaw", &T::doppler_sigma_yaw)
        .def_readwrite("match_covariance_scale", &T::match_covariance_scale)
        .def_readwrite("rapp_covariance_scale", &T::rapp_covariance_scale)
        .def_readwrite("match_sigma_x", &T::match_sigma_x)
        .def_readwrite("match_sigma_y", &T::match_sigma_y)
        .def_readwrite("match_sigma_yaw", &T::match_sigma_yaw)
        .def_readwrite("icp_sigma_x", &T::icp_sigma_x)
        .def_readwrite("icp_sigma_y", &T::icp_sigma_y)
        .def_readwrite("icp_sigma_yaw", &T::icp_sigma_yaw)
        .def_readwrite("yaw_rate_bias_sigma", &T::yaw_rate_bias_sigma)
        .def_readwrite("yaw_rate_bias_walk", &T::yaw_rate_bias_walk);
  }
  {
    using T = AutomotiveMotionGateOptions;
    optionsClass<T>(m, "AutomotiveMotionGateOptions", "radar_ndt/odometry/motion_gate.h")
        .def_readwrite("enabled", &T::enabled)
        .def_readwrite("max_acceleration", &T::max_acceleration)
        .def_readwrite("match_sigma_xy", &T::match_sigma_xy)
        .def_readwrite("match_sigma_yaw", &T::match_sigma_yaw)
        .def_readwrite("chi2_threshold", &T::chi2_threshold);
  }
  {
    using T = AutomotiveOdometryOptions;
    auto c = optionsClass<T>(m, "AutomotiveOdometryOptions", "radar_ndt/odometry/automotive_odometry.h");
    c.def_readwrite("submap_size", &T::submap_size)
        .def_readwrite("map_cycles", &T::map_cycles)
        .def_readwrite("fuse_doppler", &T::fuse_doppler)
        .def_readwrite("fusion", &T::fusion)
        .def_readwrite("grid", &T::grid)
        .def_readwrite("grid_step", &T::grid_step)
        .def_readwrite("max_retries", &T::max_retries)
        .def_readwrite("gate", &T::gate)
        .def_readwrite("stale_velocity_sigma", &T::stale_velocity_sigma)
        .def_readwrite("min_points", &T::min_points)
        .def_readwrite("doppler_weights", &T::doppler_weights)
        .def_readwrite("doppler_weight_sigma", &T::doppler_weight_sigma)
        .def_readwrite("doppler_weight_rounds", &T::doppler_weight_rounds)
        .def("paper", &T::paper, py::arg("n"),
             "These options in the paper's configuration: submap-to-submap with N = n, no fusion.");
    enumField(c, "mode", &T::mode, &parseAutomotiveMatchMode, &modeName);
  }
  {
    using T = AutomotiveRunOptions;
    optionsClass<T>(m, "AutomotiveRunOptions", "radar_ndt/pipeline/automotive_run.h")
        .def_readwrite("matcher", &T::matcher)
        .def_readwrite("sequence", &T::sequence)
        .def_readwrite("front_end", &T::front_end)
        .def_readwrite("odometry", &T::odometry)
        .def_readwrite("max_cycles", &T::max_cycles)
        .def_readwrite("threads", &T::threads);
  }
  {
    using T = EvaluationOptions;
    optionsClass<T>(m, "EvaluationOptions", "radar_ndt/evaluation/report.h")
        .def_readwrite("kitti_lengths", &T::kitti_lengths)
        .def_readwrite("kitti_step", &T::kitti_step)
        .def_readwrite("one_meter_length", &T::one_meter_length)
        .def_readwrite("frame_step", &T::frame_step);
  }
}

}  // namespace

void bindOptions(py::module_& m) {
  bindMatcherOptions(m);
  bindScanningOptions(m);
  bindAutomotiveOptions(m);
  m.def(
      "with_method",
      [](const AutomotiveRunOptions& o, const std::string& method) { return withMethod(o, parseMethod(method)); },
      py::arg("options"), py::arg("method"),
      "The automotive run options set for `method` and what it needs beyond it (rapp-ndt: Doppler "
      "weights, moving detections kept), as radar_odometry --method sets them.");
}

}  // namespace python
}  // namespace radar_ndt

// The front-ends (scanning threshold, chirp correction, automotive cycle), the two odometries step
// by step, and the whole runs as radar_odometry runs them. Long calls run without the GIL.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "keywords.h"
#include "radar_ndt/evaluation/report.h"
#include "radar_ndt/evaluation/run_report.h"
#include "radar_ndt/frontend/voxel_merge.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/scanning_run.h"

namespace radar_ndt {
namespace python {

namespace {

py::dict countersDict(const OdometryCounters& c) {
  py::dict d;
  d["cycles"] = c.cycles;
  d["first"] = c.first;
  d["matched"] = c.matched;
  d["retried"] = c.retried;
  d["fallbacks"] = c.fallbacks;
  d["dead_reckoned"] = c.dead_reckoned;
  d["skipped"] = c.skipped;
  d["bridged"] = c.bridged;
  d["too_few_points"] = c.too_few_points;
  d["stale_velocity"] = c.stale_velocity;
  d["shift_halved"] = c.shift_halved;
  d["slow"] = c.slow;
  d["not_converged"] = c.not_converged;
  d["rejected"] = c.rejected;
  d["poor_fit"] = c.poor_fit;
  d["mostly_unmatched"] = c.mostlyUnmatched();
  return d;
}

void bindPowerThreshold(py::module_& m) {
  py::class_<PowerThreshold>(m, "PowerThreshold",
                             "The scanning front-end (paper, Sec. III-A): polar scan to points above the power "
                             "threshold, in the vehicle frame.\n\nPowerThreshold(**PowerThresholdOptions).")
      .def(py::init([](const py::kwargs& kw) {
        return std::make_unique<PowerThreshold>(withKeywords(PowerThresholdOptions{}, kw, "PowerThreshold"));
      }))
      .def_property_readonly("options", &PowerThreshold::options)
      .def(
          "points",
          [](const PowerThreshold& f, const PolarScan& scan) {
            pcl::PointCloud<PointRadar> cloud;
            {
              py::gil_scoped_release release;
              f.compute(scan, cloud);
            }
            return toArray(cloud);
          },
          py::arg("scan"),
          "The thresholded points of `scan`: (N, 11) POINT_FIELDS with power, covariance and each point's time "
          "offset from the scan's reference time.")
      .def(
          "cartesian_image",
          [](const PowerThreshold& f, const PolarScan& scan) {
            CartesianImage image;
            {
              py::gil_scoped_release release;
              image = f.cartesianImage(scan);
            }
            py::array_t<float> a({image.size, image.size});
            std::copy(image.power.begin(), image.power.end(), a.mutable_data());
            return py::make_tuple(a, image.resolution);
          },
          py::arg("scan"),
          "(image, metres per pixel): the Cartesian power image, row 0 the far front, column 0 the far left, "
          "-1 outside the ring.");
}

void bindChirpsAndVoxels(py::module_& m) {
  m.def(
      "correct_chirps",
      [](PolarScan& scan, double max_range, const py::kwargs& kw) {
        const auto o = withKeywords(ChirpCorrectionOptions{}, kw, "correct_chirps");
        ChirpShiftEstimate e;
        {
          py::gil_scoped_release release;
          e = correctChirps(scan, o, max_range);
        }
        py::dict d;
        d["valid"] = e.valid;
        d["u"] = Eigen::Vector2d(e.u);
        d["pairs"] = e.pairs;
        d["rms"] = e.rms;
        return d;
      },
      py::arg("scan"), py::arg("max_range") = 1e300,
      "Finds and undoes, in place, the up/down-chirp range shifts of a scan with chirp types (Boreas 2024); "
      "returns the estimate {valid, u (m, vehicle frame), pairs, rms}. Keywords: ChirpCorrectionOptions.");
  m.def(
      "merge_voxels",
      [](const py::object& points, double size) {
        const auto in = toCloud(points, "points", true);
        pcl::PointCloud<PointRadar> out;
        mergeVoxels(*in, size, out);
        return toArray(out);
      },
      py::arg("points"), py::arg("size"),
      "Points merged per square voxel of `size` m (position, time offset and covariance averaged, power the "
      "strongest): how the scanning run feeds PCL's matchers.");
}

void bindScanningFrontEnd(py::module_& m) {
  bindPowerThreshold(m);
  bindChirpsAndVoxels(m);
}

void bindAutomotiveFrontEnd(py::module_& m) {
  py::class_<EgoVelocity>(m, "EgoVelocity",
                          "A Doppler ego-velocity fit (radar_ndt/frontend/ego_velocity.h): (vx, vy, yaw rate) in the "
                          "vehicle frame, m/s and rad/s.")
      .def_readonly("velocity", &EgoVelocity::velocity)
      .def_readonly("covariance", &EgoVelocity::covariance)
      .def_readonly("points", &EgoVelocity::points, "detections offered")
      .def_readonly("inliers", &EgoVelocity::inliers, "detections consistent with it (stationary)")
      .def_readonly("residual_rms", &EgoVelocity::residual_rms)
      .def_readonly("valid", &EgoVelocity::valid, "bool: False for too few or degenerate detections")
      .def_readonly("nonholonomic", &EgoVelocity::nonholonomic, "bool: the fit took vy = 0 (radars at one place)")
      .def_readonly("forward_only", &EgoVelocity::forward_only,
                    "bool: the radars sat on the rear axle's line: the forward speed alone, the yaw rate unknown");
  py::class_<ProcessedCycle>(
      m, "ProcessedCycle",
      "A cycle after the automotive front-end: one planar cloud in the vehicle frame at the reference time.")
      .def_readonly("timestamp_us", &ProcessedCycle::timestamp_us)
      .def_property_readonly("points", [](const ProcessedCycle& c) { return toArray(*c.cloud); })
      .def_readonly("ego_velocity", &ProcessedCycle::ego, "the cycle's Doppler EgoVelocity")
      .def_readonly("raw_points", &ProcessedCycle::raw_points)
      .def_readonly("removed_moving", &ProcessedCycle::removed_moving);
  py::class_<AutomotiveFrontEnd>(m, "AutomotiveFrontEnd",
                                 "Covariances, Doppler ego-velocity, moving detections removed, sweeps moved to the "
                                 "reference time.\n\nAutomotiveFrontEnd(**AutomotiveFrontEndOptions).")
      .def(py::init([](const py::kwargs& kw) {
        return std::make_unique<AutomotiveFrontEnd>(
            withKeywords(AutomotiveFrontEndOptions{}, kw, "AutomotiveFrontEnd"));
      }))
      .def(
          "process",
          [](const AutomotiveFrontEnd& f, const RadarCycle& cycle, const EgoVelocity* fallback) {
            py::gil_scoped_release release;
            return f.process(cycle, fallback);
          },
          py::arg("cycle"), py::arg("fallback") = nullptr,
          "The cycle through the front-end. When its own ego-velocity cannot be fitted, `fallback` (the last "
          "valid EgoVelocity, as the run passes it) filters and compensates it; its ego_velocity.valid stays "
          "False.");
}

void bindFrontEnds(py::module_& m) {
  bindScanningFrontEnd(m);
  bindAutomotiveFrontEnd(m);
}

void bindStep(py::module_& m) {
  py::class_<OdometryStep>(m, "OdometryStep", "What one scan or cycle did (radar_ndt/odometry/odometry_step.h).")
      .def_readonly("timestamp_us", &OdometryStep::timestamp_us)
      .def_readonly("pose", &OdometryStep::pose, "numpy.ndarray: (x, y, yaw) in the first frame")
      .def_readonly("motion", &OdometryStep::motion, "numpy.ndarray: (x, y, yaw) of this frame in the previous one")
      .def_readonly("prior_motion", &OdometryStep::prior_motion,
                    "numpy.ndarray: the initial guess, the Doppler integral (scanning: constant velocity)")
      .def_property_readonly(
          "status", [](const OdometryStep& s) { return std::string(toString(s.status)); },
          "str: first, matched, retried, fallback, dead-reckoned, skipped or bridged")
      .def_readonly("attempts", &OdometryStep::attempts)
      .def_readonly("too_few_points", &OdometryStep::too_few_points)
      .def_readonly("grid", &OdometryStep::grid)
      .def_readonly("match_ms", &OdometryStep::match_ms)
      .def_readonly("source_points", &OdometryStep::source_points)
      .def_readonly("target_points", &OdometryStep::target_points)
      .def_readonly("chi2", &OdometryStep::chi2)
      .def_readonly("velocity_valid", &OdometryStep::velocity_valid)
      .def_readonly("match_motion", &OdometryStep::match_motion)
      .def_readonly("match_covariance", &OdometryStep::match_covariance)
      .def_readonly("power_shift", &OdometryStep::power_shift)
      .def_readonly("keyframe", &OdometryStep::keyframe)
      .def("__repr__", [](const OdometryStep& s) {
        return "OdometryStep(timestamp_us=" + std::to_string(s.timestamp_us) + ", status='" + toString(s.status) +
               "', pose=(" + std::to_string(s.pose.x()) + ", " + std::to_string(s.pose.y()) + ", " +
               std::to_string(s.pose.z()) + "))";
      });
}

/// Matcher options for an odometry: the run's defaults, `method`, then `matcher` keywords.
MatcherOptions matcherOptions(MatcherOptions base, const std::string& method, const py::object& matcher) {
  if (!method.empty()) base.method = method;
  if (!matcher.is_none()) base = withKeywords(base, matcher.cast<py::dict>(), "matcher");
  base.validate();
  return base;
}

void bindScanningOdometry(py::module_& m) {
  bindStep(m);
  py::class_<ScanningOdometry>(
      m, "ScanningOdometry",
      "The scanning pipeline after the front-end, scan by scan (radar_ndt/odometry/scanning_odometry.h).\n\n"
      "ScanningOdometry(method='pw-ndt', matcher=None, **ScanningOdometryOptions): matcher a dict of "
      "MatcherOptions fields (default: the scanning radars', MatcherOptions::forScanning).")
      .def(py::init([](const std::string& method, const py::object& matcher, const py::kwargs& kw) {
             const MatcherOptions mo = matcherOptions(MatcherOptions::forScanning(), method, matcher);
             if (findMatcher(mo.method).uses.automotiveOnly())
               throw std::invalid_argument("method " + mo.method +
                                           " needs Doppler or a car's CAN bus, which scanning sequences do not have");
             const auto o = withKeywords(ScanningOdometryOptions{}, kw, "ScanningOdometry", "method, matcher");
             return std::make_unique<ScanningOdometry>(o, makeMatcher(mo));
           }),
           py::arg("method") = "pw-ndt", py::arg("matcher") = py::none())
      .def(
          "add_scan",
          [](ScanningOdometry& o, std::int64_t timestamp_us, const py::object& points) {
            const auto cloud = toCloud(points, "points", true);
            py::gil_scoped_release release;
            return o.addScan(ScanFrame{timestamp_us, cloud});
          },
          py::arg("timestamp_us"), py::arg("points"),
          "Adds a thresholded scan (PowerThreshold.points: vehicle frame, time offsets from timestamp_us); "
          "returns its OdometryStep.")
      .def("bridge", &ScanningOdometry::bridge, py::arg("timestamp_us"),
           "A scan that could not be read: a bridged step continuing the last motion.")
      .def_property_readonly("steps", &ScanningOdometry::steps)
      .def_property_readonly("counters", [](const ScanningOdometry& o) { return countersDict(o.counters()); })
      .def_property_readonly("trajectory", &ScanningOdometry::trajectory)
      .def_property_readonly(
          "keyframe_points",
          [](const ScanningOdometry& o) {
            const auto c = o.keyframeCloud();
            return c ? toArray(*c) : toArray(pcl::PointCloud<PointRadar>());
          },
          "what the next scan is matched against");
}

void bindAutomotiveOdometry(py::module_& m) {
  py::class_<AutomotiveOdometry>(
      m, "AutomotiveOdometry",
      "The automotive pipeline after the front-end, cycle by cycle "
      "(radar_ndt/odometry/automotive_odometry.h).\n\nAutomotiveOdometry(method='pw-ndt', matcher=None, "
      "**AutomotiveOdometryOptions); method doppler dead-reckons with the ego-velocity.")
      .def(py::init([](const std::string& method, const py::object& matcher, const py::kwargs& kw) {
             AutomotiveRunOptions run = withMethod(AutomotiveRunOptions{}, method);
             run.odometry = withKeywords(run.odometry, kw, "AutomotiveOdometry", "method, matcher");
             const MatcherOptions mo = matcherOptions(run.matcher, "", matcher);
             return std::make_unique<AutomotiveOdometry>(run.odometry, makeMatcher(mo));
           }),
           py::arg("method") = "pw-ndt", py::arg("matcher") = py::none())
      .def(
          "add",
          [](AutomotiveOdometry& o, const ProcessedCycle& cycle) {
            py::gil_scoped_release release;
            return o.add(cycle);
          },
          py::arg("cycle"), "Adds a front-end cycle (AutomotiveFrontEnd.process); returns its OdometryStep.")
      .def("bridge", &AutomotiveOdometry::bridge, py::arg("timestamp_us"))
      .def_property_readonly("steps", &AutomotiveOdometry::steps)
      .def_property_readonly("counters", [](const AutomotiveOdometry& o) { return countersDict(o.counters()); })
      .def_property_readonly("trajectory", &AutomotiveOdometry::trajectory);
}

void bindOdometries(py::module_& m) {
  bindScanningOdometry(m);
  bindAutomotiveOdometry(m);
}

}  // namespace

void bindFrontEnd(py::module_& m) {
  bindFrontEnds(m);
}
void bindOdometry(py::module_& m) {
  bindOdometries(m);
}

}  // namespace python
}  // namespace radar_ndt

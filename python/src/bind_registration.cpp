// The matchers: pw-ndt (radar_ndt::WeightedNDT2D for PointRadar) and PCL's NDT and ICP as the
// pipelines build them (makeMatcher), each with align(source, target, guess) on numpy arrays.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>

#include "bindings.h"
#include "keywords.h"
#include "radar_ndt/odometry/matcher.h"

namespace radar_ndt {
namespace python {

namespace {

using WeightedNdt = WeightedNDT2D<PointRadar, PointRadar>;
using PclNdt = pcl::NormalDistributionsTransform<PointRadar, PointRadar>;
using PclIcp = pcl::IterativeClosestPoint<PointRadar, PointRadar>;

/// What PCL's matchers report of one align().
struct PclAlignResult {
  Eigen::Matrix4f final_transformation = Eigen::Matrix4f::Identity();
  bool converged = false;
  int iterations = -1;  ///< NDT only; ICP does not report it
  double fitness_score = 0;
};

/// The cloud of `points`, the target and source set and align() run without the GIL.
void alignArrays(RadarRegistration& r, const py::object& source, const py::object& target, const py::object& guess) {
  const auto src = toCloud(source, "source");
  const auto tgt = toCloud(target, "target");
  const Eigen::Matrix4f g = guess.is_none() ? Eigen::Matrix4f::Identity() : toMatrix4f(guess, "guess");
  py::gil_scoped_release release;
  r.setInputTarget(tgt);
  r.setInputSource(src);
  pcl::PointCloud<PointRadar> out;
  r.align(out, g);
}

Pose2 poseOf(const Eigen::Matrix4f& T) {
  return toPose2(T.cast<double>().eval());
}

/// A PCL matcher as the pipelines build it, its keyword arguments applied (PCL's own setters).
class PclMatcher {
 public:
  PclMatcher(const std::string& method, const py::kwargs& kw) : ndt_(method == "pcl-ndt") {
    MatcherOptions o;  // the grid's default is MatcherOptions'
    o.method = method;
    const char* grid_key = ndt_ ? "resolution" : "max_correspondence_distance";
    if (kw.contains(grid_key)) o.grid = keywordAs<double>(kw[grid_key], grid_key);
    if (!(o.grid > 0)) throw std::invalid_argument(std::string(grid_key) + " must be > 0");
    adapter_ = makeMatcher(o);
    for (auto item : kw) {
      const std::string k = py::str(item.first);
      if (k == grid_key) continue;
      set(k, item.second);
    }
  }

  void set(const std::string& key, const py::handle& value) {
    RadarRegistration& r = adapter_.registration();
    if (key == "max_iterations")
      r.setMaximumIterations(positive<int>(key, value));
    else if (key == "transformation_epsilon")
      r.setTransformationEpsilon(positive<double>(key, value));
    else if (key == "step_size" && ndt_)
      static_cast<PclNdt&>(r).setStepSize(positive<double>(key, value));
    else if (key == "euclidean_fitness_epsilon" && !ndt_)
      r.setEuclideanFitnessEpsilon(positive<double>(key, value));
    else
      throw py::type_error("unknown option '" + key + "' of " + name() + "; options: " +
                           (ndt_ ? "resolution, step_size, max_iterations, transformation_epsilon"
                                 : "max_correspondence_distance, max_iterations, transformation_epsilon, "
                                   "euclidean_fitness_epsilon"));
  }

  PclAlignResult align(const py::object& source, const py::object& target, const py::object& guess) {
    RadarRegistration& r = adapter_.registration();
    alignArrays(r, source, target, guess);
    PclAlignResult out;
    out.final_transformation = r.getFinalTransformation();
    out.converged = r.hasConverged();
    if (ndt_) out.iterations = static_cast<PclNdt&>(r).getFinalNumIteration();
    py::gil_scoped_release release;
    out.fitness_score = r.getFitnessScore();
    return out;
  }

  std::string name() const { return ndt_ ? "NDT" : "ICP"; }

 private:
  template <typename T>
  static T positive(const std::string& key, const py::handle& value) {
    const T v = keywordAs<T>(value, key);
    if (!(v > 0)) throw std::invalid_argument(key + " must be > 0");
    return v;
  }
  bool ndt_;  ///< PCL's NDT, else its ICP
  MatcherAdapter adapter_;
};
// One Python class each.
struct PclNdtMatcher : PclMatcher {
  explicit PclNdtMatcher(const py::kwargs& kw) : PclMatcher("pcl-ndt", kw) {}
};
struct PclIcpMatcher : PclMatcher {
  explicit PclIcpMatcher(const py::kwargs& kw) : PclMatcher("pcl-icp", kw) {}
};

void bindResults(py::module_& m) {
  py::class_<WeightedNDT2DResult>(m, "WeightedNDT2DResult",
                                  "What one WeightedNDT2D.align() found and why it stopped "
                                  "(radar_ndt/registration/weighted_ndt_2d_result.h).")
      .def_readonly(
          "final_transformation", &WeightedNDT2DResult::final_transformation,
          "numpy.ndarray: the source in the target's frame (a 4x4 float32 matrix), as PCL's getFinalTransformation()")
      .def_property_readonly(
          "transform", [](const WeightedNDT2DResult& r) { return toSe2Matrix(poseOf(r.final_transformation)); },
          "numpy.ndarray: 3x3 SE(2) matrix of final_transformation")
      .def_property_readonly(
          "pose", [](const WeightedNDT2DResult& r) { return Eigen::Vector3d(poseOf(r.final_transformation)); },
          "numpy.ndarray: (x, y, yaw) of final_transformation")
      .def_readonly("converged", &WeightedNDT2DResult::converged,
                    "bool: converged and not degenerate, as hasConverged()")
      .def_property_readonly(
          "status", [](const WeightedNDT2DResult& r) { return std::string(toString(r.status)); },
          "str: why it stopped, not-run, converged, stuck, iteration-limit or degenerate")
      .def_readonly("iterations", &WeightedNDT2DResult::iterations)
      .def_readonly("final_cost", &WeightedNDT2DResult::final_cost)
      .def_property_readonly("score_per_point", &WeightedNDT2DResult::scorePerPoint)
      .def_readonly("hessian", &WeightedNDT2DResult::hessian, "of the cost at the solution, in (x, y, yaw)")
      .def_readonly("covariance", &WeightedNDT2DResult::pose_covariance,
                    "of (x, y, yaw); infinite diagonal when degenerate")
      .def_readonly("num_source_points", &WeightedNDT2DResult::num_source_points)
      .def_readonly("num_matched_points", &WeightedNDT2DResult::num_matched_points)
      .def_property_readonly("degenerate", &WeightedNDT2DResult::degenerate)
      .def("__repr__", [](const WeightedNDT2DResult& r) {
        const Pose2 p = poseOf(r.final_transformation);
        return "WeightedNDT2DResult(status='" + std::string(toString(r.status)) + "', pose=(" + std::to_string(p.x()) +
               ", " + std::to_string(p.y()) + ", " + std::to_string(p.z()) +
               "), iterations=" + std::to_string(r.iterations) + ")";
      });
  py::class_<PclAlignResult>(m, "PclAlignResult", "What PCL's NDT or ICP reported of one align().")
      .def_readonly("final_transformation", &PclAlignResult::final_transformation)
      .def_property_readonly("transform",
                             [](const PclAlignResult& r) { return toSe2Matrix(poseOf(r.final_transformation)); })
      .def_property_readonly("pose",
                             [](const PclAlignResult& r) { return Eigen::Vector3d(poseOf(r.final_transformation)); })
      .def_readonly("converged", &PclAlignResult::converged)
      .def_property_readonly("status",
                             [](const PclAlignResult& r) { return r.converged ? "converged" : "not-converged"; })
      .def_readonly("iterations", &PclAlignResult::iterations, "NDT's iterations; -1 for ICP, which does not say")
      .def_readonly("fitness_score", &PclAlignResult::fitness_score,
                    "PCL's getFitnessScore(): mean squared distance to the nearest target point");
}

/// WeightedNDT2D(**settings): the settings as keywords, resolution=g and PCL's own three.
std::shared_ptr<WeightedNdt> makeWeightedNdt(const py::kwargs& kw) {
  auto r = std::make_shared<WeightedNdt>();
  WeightedNDT2DSettings s = r->getSettings();
  py::dict rest;
  for (auto item : kw) {
    const std::string k = py::str(item.first);
    if (k == "resolution")
      s.resolutions = {keywordAs<float>(item.second, k)};
    else if (k == "max_iterations")
      r->setMaximumIterations(keywordAs<int>(item.second, k));
    else if (k == "transformation_epsilon")
      r->setTransformationEpsilon(keywordAs<double>(item.second, k));
    else if (k == "rotation_epsilon")
      r->setTransformationRotationEpsilon(keywordAs<double>(item.second, k));
    else
      rest[item.first] = item.second;
  }
  applyKeywords(py::cast(&s, py::return_value_policy::reference), rest, "WeightedNDT2D",
                "resolution, max_iterations, transformation_epsilon, rotation_epsilon");
  r->setSettings(s);
  if (r->getMaximumIterations() < 1) throw std::invalid_argument("max_iterations must be >= 1");
  return r;
}

}  // namespace

void bindWeightedNdt(py::module_& m) {
  bindResults(m);
  py::class_<WeightedNdt, std::shared_ptr<WeightedNdt>>(
      m, "WeightedNDT2D",
      "The paper's weighted probabilistic NDT (radar_ndt::WeightedNDT2D for PointRadar).\n\n"
      "WeightedNDT2D(**settings): every WeightedNDT2DSettings field as a keyword (resolutions, "
      "power_shift, cell_lookup, ...), plus resolution=g (one grid), and PCL's own max_iterations, "
      "transformation_epsilon and rotation_epsilon. A bad value raises ValueError naming it.")
      .def(py::init(&makeWeightedNdt))
      .def_property(
          "settings", [](const WeightedNdt& r) { return r.getSettings(); },
          [](WeightedNdt& r, const WeightedNDT2DSettings& s) { r.setSettings(s); },
          "a copy of the settings; assign a WeightedNDT2DSettings to change them (validated)")
      .def_property("max_iterations", &WeightedNdt::getMaximumIterations, &WeightedNdt::setMaximumIterations)
      .def_property("transformation_epsilon", &WeightedNdt::getTransformationEpsilon,
                    &WeightedNdt::setTransformationEpsilon)
      .def_property("rotation_epsilon", &WeightedNdt::getTransformationRotationEpsilon,
                    &WeightedNdt::setTransformationRotationEpsilon)
      .def(
          "align",
          [](WeightedNdt& r, const py::object& source, const py::object& target, const py::object& guess) {
            alignArrays(r, source, target, guess);
            return r.getResult();
          },
          py::arg("source"), py::arg("target"), py::arg("guess") = py::none(),
          "Aligns `source` to `target` from `guess` (3x3 SE(2), 4x4 or (x, y, yaw); default identity).\n"
          "Points: (N, 3) x, y, power; (N, 2) x, y (power 1); or (N, 11) radar_ndt.POINT_FIELDS. Returns a "
          "WeightedNDT2DResult. The GIL is released while it runs.")
      .def(
          "set_source_sweep",
          [](WeightedNdt& r, double interval, const py::object& previous_pose) {
            r.setSourceSweep(interval, poseOf(toMatrix4f(previous_pose, "previous_pose")));
          },
          py::arg("interval"), py::arg("previous_pose") = py::make_tuple(0.0, 0.0, 0.0),
          "The source sweep's motion inside the match (docs/matcher.md): each source point, at its time "
          "offset (POINT_FIELDS' time_offset column) within its sweep, is placed by the constant-velocity "
          "motion over the step of `interval` seconds from `previous_pose` (the previous scan's pose in the "
          "target's frame; 3x3, 4x4 or (x, y, yaw), default identity) to the source's. Holds for every align "
          "until clear_source_sweep(); raises ValueError for an interval not positive and finite.")
      .def("clear_source_sweep", &WeightedNdt::clearSourceSweep, "Back to one rigid pose for the whole source.")
      .def_property_readonly("has_source_sweep", &WeightedNdt::hasSourceSweep)
      .def_property_readonly(
          "result", [](const WeightedNdt& r) { return r.getResult(); }, "the last align()'s result");
}

void bindPclMatchers(py::module_& m) {
  py::class_<PclNdtMatcher>(m, "NDT",
                            "PCL's pcl::NormalDistributionsTransform for PointRadar, set as RadarNDT compares it: "
                            "NDT(resolution=3.0, step_size=0.5, transformation_epsilon=1e-4, max_iterations=50).")
      .def(py::init<const py::kwargs&>())
      .def("align", &PclMatcher::align, py::arg("source"), py::arg("target"), py::arg("guess") = py::none(),
           "Aligns as WeightedNDT2D.align does (the power column is not used); returns a PclAlignResult.");
  py::class_<PclIcpMatcher>(m, "ICP",
                            "PCL's pcl::IterativeClosestPoint for PointRadar, set as RadarNDT compares it: "
                            "ICP(max_correspondence_distance=3.0, max_iterations=50, transformation_epsilon=1e-8, "
                            "euclidean_fitness_epsilon=1e-8).")
      .def(py::init<const py::kwargs&>())
      .def("align", &PclMatcher::align, py::arg("source"), py::arg("target"), py::arg("guess") = py::none(),
           "Aligns as WeightedNDT2D.align does (the power column is not used); returns a PclAlignResult.");
}

void bindRegistration(py::module_& m) {
  bindWeightedNdt(m);
  bindPclMatchers(m);
}

}  // namespace python
}  // namespace radar_ndt

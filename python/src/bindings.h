#pragma once
// What the Python module's binding files share: the conversions between numpy arrays and the
// library's clouds, poses and trajectories, and the registration of each part of the module.
// Arrays are checked here, before any C++ code sees them: a bad shape or a non-finite value raises
// ValueError naming the argument, never reaches an algorithm.

#include <cstdint>
#include <string>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/point_types.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {
namespace python {

namespace py = pybind11;

/// The columns of a full point array, PointRadar's fields in order (radar_ndt.POINT_FIELDS).
constexpr const char* kPointFields[] = {"x",      "y",      "z",       "power",       "rcs",      "cov_xx",
                                        "cov_xy", "cov_yy", "doppler", "time_offset", "sensor_id"};
constexpr int kPointFieldCount = 11;

/// An (N, 2) x, y; (N, 3) x, y, power; or (N, 11) array (kPointFields) as a cloud (z = 0 unless
/// given). ValueError naming `name` for another shape, a non-finite value, a sensor id that is not
/// an integer in 0..65535, or (unless `allow_empty`) no rows.
pcl::PointCloud<PointRadar>::Ptr toCloud(const py::handle& array, const char* name, bool allow_empty = false);
/// A cloud as an (N, 11) float64 array (kPointFields); exact, every field is a float32 or uint16.
py::array_t<double> toArray(const pcl::PointCloud<PointRadar>& cloud);

/// A planar guess or pose: a 3x3 homogeneous SE(2) matrix, a 4x4 homogeneous matrix or (x, y,
/// yaw). ValueError naming `name` otherwise.
Eigen::Matrix4f toMatrix4f(const py::handle& value, const char* name);
/// A 3x3 homogeneous SE(2) matrix of a pose.
py::array_t<double> toSe2Matrix(const Pose2& pose);

/// A Trajectory's poses as an (N, 4, 4) float64 array and its stamps as (N,) (empty without).
py::array_t<double> posesArray(const Trajectory& trajectory);
py::array_t<double> stampsArray(const Trajectory& trajectory);
/// A Trajectory from (N, 4, 4), (N, 3, 3) SE(2) or (N, 3) x, y, yaw poses and optional (N,) stamps.
Trajectory toTrajectory(const py::handle& poses, const py::handle& stamps, const char* name);

/// A 1-D array of `values` (copied).
template <typename T>
py::array_t<T> vectorArray(const std::vector<T>& values) {
  py::array_t<T> a(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), a.mutable_data());
  return a;
}

// Each part of the module registers itself (module.cpp calls them in this order).
void bindOptions(py::module_& m);
void bindRegistration(py::module_& m);
void bindIo(py::module_& m);
void bindFrontEnd(py::module_& m);
void bindOdometry(py::module_& m);
void bindRuns(py::module_& m);
void bindEvaluation(py::module_& m);

}  // namespace python
}  // namespace radar_ndt

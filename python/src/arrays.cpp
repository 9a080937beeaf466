// numpy arrays to and from the library's clouds, poses and trajectories (bindings.h).

#include <cmath>
#include <limits>

#include "bindings.h"

namespace radar_ndt {
namespace python {

namespace {

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

Doubles asDoubles(const py::handle& value, const char* name) {
  if (value.is_none()) throw py::value_error(std::string(name) + ": None is not an array");
  Doubles a = Doubles::ensure(value);
  if (!a) throw py::value_error(std::string(name) + ": not convertible to an array of numbers");
  return a;
}

std::string shapeText(const Doubles& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

}  // namespace

pcl::PointCloud<PointRadar>::Ptr toCloud(const py::handle& array, const char* name, bool allow_empty) {
  const Doubles a = asDoubles(array, name);
  const std::string n(name);
  if (a.ndim() != 2 || (a.shape(1) != 2 && a.shape(1) != 3 && a.shape(1) != kPointFieldCount))
    throw py::value_error(n +
                          ": expected an (N, 2) x, y, (N, 3) x, y, power or (N, 11) array of "
                          "radar_ndt.POINT_FIELDS, got shape " +
                          shapeText(a));
  const py::ssize_t rows = a.shape(0), cols = a.shape(1);
  if (rows == 0 && !allow_empty) throw py::value_error(n + ": no points (an empty array)");
  auto cloud = pcl::make_shared<pcl::PointCloud<PointRadar>>();
  cloud->resize(static_cast<std::size_t>(rows));
  const double* d = a.data();
  for (py::ssize_t i = 0; i < rows; ++i) {
    const double* r = d + i * cols;
    for (py::ssize_t c = 0; c < cols; ++c)
      if (!std::isfinite(r[c]))
        throw py::value_error(n + ": row " + std::to_string(i) + ", column " +
                              (cols == 3 && c == 2 ? "power" : kPointFields[c]) + " is not finite (" +
                              std::to_string(r[c]) + ")");
    PointRadar& p = (*cloud)[static_cast<std::size_t>(i)];
    p.x = static_cast<float>(r[0]);
    p.y = static_cast<float>(r[1]);
    if (cols == 3) p.power = static_cast<float>(r[2]);
    if (cols == kPointFieldCount) {
      const double id = r[10];
      if (id < 0 || id > std::numeric_limits<std::uint16_t>::max() || id != std::floor(id))
        throw py::value_error(n + ": row " + std::to_string(i) + ", column sensor_id is not an integer in 0..65535");
      p.z = static_cast<float>(r[2]);
      p.power = static_cast<float>(r[3]);
      p.rcs = static_cast<float>(r[4]);
      p.cov_xx = static_cast<float>(r[5]);
      p.cov_xy = static_cast<float>(r[6]);
      p.cov_yy = static_cast<float>(r[7]);
      p.doppler = static_cast<float>(r[8]);
      p.time_offset = static_cast<float>(r[9]);
      p.sensor_id = static_cast<std::uint16_t>(id);
    }
  }
  return cloud;
}

py::array_t<double> toArray(const pcl::PointCloud<PointRadar>& cloud) {
  py::array_t<double> a({static_cast<py::ssize_t>(cloud.size()), static_cast<py::ssize_t>(kPointFieldCount)});
  double* d = a.mutable_data();
  for (const PointRadar& p : cloud.points) {
    const double row[kPointFieldCount] = {p.x,
                                          p.y,
                                          p.z,
                                          p.power,
                                          p.rcs,
                                          p.cov_xx,
                                          p.cov_xy,
                                          p.cov_yy,
                                          p.doppler,
                                          p.time_offset,
                                          static_cast<double>(p.sensor_id)};
    d = std::copy(row, row + kPointFieldCount, d);
  }
  return a;
}

Eigen::Matrix4f toMatrix4f(const py::handle& value, const char* name) {
  const Doubles a = asDoubles(value, name);
  const std::string n(name);
  const double* d = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i)
    if (!std::isfinite(d[i])) throw py::value_error(n + ": not finite");
  if (a.ndim() == 1 && a.shape(0) == 3) return toMatrix4<float>(Pose2(d[0], d[1], d[2]));
  if (a.ndim() == 2 && a.shape(0) == a.shape(1) && (a.shape(0) == 3 || a.shape(0) == 4)) {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    if (a.shape(0) == 4) {
      m = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(d);
    } else {
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> s(d);
      m.topLeftCorner<2, 2>() = s.topLeftCorner<2, 2>();
      m.topRightCorner<2, 1>() = s.topRightCorner<2, 1>();
    }
    return m.cast<float>();
  }
  throw py::value_error(n + ": expected a 3x3 SE(2) matrix, a 4x4 matrix or (x, y, yaw), got shape " + shapeText(a));
}

py::array_t<double> toSe2Matrix(const Pose2& pose) {
  py::array_t<double> a({3, 3});
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(a.mutable_data()) = toIsometry2(pose).matrix();
  return a;
}

py::array_t<double> posesArray(const Trajectory& trajectory) {
  py::array_t<double> a({static_cast<py::ssize_t>(trajectory.size()), py::ssize_t{4}, py::ssize_t{4}});
  double* d = a.mutable_data();
  for (const Eigen::Isometry3d& T : trajectory.poses) {
    Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> out(d);
    out = T.matrix();
    d += 16;
  }
  return a;
}

py::array_t<double> stampsArray(const Trajectory& trajectory) {
  return vectorArray(trajectory.stamps);
}

Trajectory toTrajectory(const py::handle& poses, const py::handle& stamps, const char* name) {
  const Doubles a = asDoubles(poses, name);
  const std::string n(name);
  const bool m4 = a.ndim() == 3 && a.shape(1) == 4 && a.shape(2) == 4;
  const bool m3 = a.ndim() == 3 && a.shape(1) == 3 && a.shape(2) == 3;
  const bool xyyaw = a.ndim() == 2 && a.shape(1) == 3;
  if (!m4 && !m3 && !xyyaw)
    throw py::value_error(n + ": poses must be (N, 4, 4), (N, 3, 3) SE(2) or (N, 3) x, y, yaw, got shape " +
                          shapeText(a));
  Trajectory t;
  const double* d = a.data();
  const py::ssize_t stride = m4 ? 16 : m3 ? 9 : 3;
  for (py::ssize_t i = 0; i < a.shape(0); ++i, d += stride) {
    for (py::ssize_t k = 0; k < stride; ++k)
      if (!std::isfinite(d[k])) throw py::value_error(n + ": pose " + std::to_string(i) + " is not finite");
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    if (m4) {
      T.matrix() = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(d);
    } else if (m3) {
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> s(d);
      T.linear().topLeftCorner<2, 2>() = s.topLeftCorner<2, 2>();
      T.translation().head<2>() = s.topRightCorner<2, 1>();
    } else {
      T = toIsometry3(Pose2(d[0], d[1], d[2]));
    }
    t.poses.push_back(T);
  }
  if (!stamps.is_none()) {
    const Doubles s = asDoubles(stamps, (n + " stamps").c_str());
    if (s.ndim() != 1 || s.shape(0) != a.shape(0))
      throw py::value_error(n + ": stamps must be (N,) with one per pose (" + std::to_string(a.shape(0)) +
                            "), got shape " + shapeText(s));
    for (py::ssize_t i = 0; i < s.shape(0); ++i) {
      if (!std::isfinite(s.data()[i])) throw py::value_error(n + ": stamp " + std::to_string(i) + " is not finite");
      if (i > 0 && !(s.data()[i] > s.data()[i - 1]))
        throw py::value_error(n + ": stamps must be strictly increasing (stamp " + std::to_string(i) + ")");
    }
    t.stamps.assign(s.data(), s.data() + s.shape(0));
  }
  return t;
}

}  // namespace python
}  // namespace radar_ndt

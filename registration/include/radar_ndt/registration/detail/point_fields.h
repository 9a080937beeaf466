#pragma once
// What WeightedNDT2D and WeightedNDT3D read from a point, for any PCL point type: fields are
// detected at compile time, so pcl::PointXYZ (power 1, no covariance), pcl::PointXYZI (intensity =
// power), radar_ndt::PointRadar (power, 2x2 covariance) and radar_ndt::PointRadar4D (power, 3x3
// covariance) all work.

#include <cmath>
#include <cstdint>

#include <Eigen/Core>
#include <pcl/point_types.h>
#include <pcl/type_traits.h>

#include "radar_ndt/point_types.h"

namespace radar_ndt {
namespace detail {

/// Power used for the weights: PointRadar's `power`, PointXYZI's `intensity`, else 1.
template <typename PointT>
inline float pointPower(const PointT& p) {
  if constexpr (pcl::traits::has_field<PointT, pcl::fields::power>::value)
    return p.power;
  else if constexpr (pcl::traits::has_field<PointT, pcl::fields::intensity>::value)
    return p.intensity;
  else {
    (void)p;
    return 1.0f;
  }
}

/// The point's time offset (s) within its sweep: PointRadar's `time_offset`; 0 for a type without
/// one or when it is not finite (the point is then placed at the sweep's reference time).
template <typename PointT>
inline double pointTimeOffset(const PointT& p) {
  if constexpr (pcl::traits::has_field<PointT, pcl::fields::time_offset>::value)
    return std::isfinite(p.time_offset) ? static_cast<double>(p.time_offset) : 0.0;
  else {
    (void)p;
    return 0.0;
  }
}

/// The point's own 2x2 position covariance, zero when the type has none.
template <typename PointT>
inline Eigen::Vector3d pointCovariance(const PointT& p) {  // (xx, xy, yy)
  if constexpr (pcl::traits::has_field<PointT, pcl::fields::cov_xx>::value)
    return Eigen::Vector3d(p.cov_xx, p.cov_xy, p.cov_yy);
  else {
    (void)p;
    return Eigen::Vector3d::Zero();
  }
}

/// The point's own 3x3 position covariance: PointRadar4D's full one, a planar type's 2x2 one with
/// nothing known in z, zero when the type has none.
template <typename PointT>
inline Eigen::Matrix3d pointCovariance3D(const PointT& p) {
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  if constexpr (pcl::traits::has_field<PointT, pcl::fields::cov_zz>::value) {
    c << p.cov_xx, p.cov_xy, p.cov_xz, p.cov_xy, p.cov_yy, p.cov_yz, p.cov_xz, p.cov_yz, p.cov_zz;
  } else if constexpr (pcl::traits::has_field<PointT, pcl::fields::cov_xx>::value) {
    c(0, 0) = p.cov_xx;
    c(0, 1) = c(1, 0) = p.cov_xy;
    c(1, 1) = p.cov_yy;
  } else {
    (void)p;
  }
  return c;
}

/// Rotates a PointRadar4D's covariance by R (R C Rᵀ); other types are left as they are.
template <typename PointT>
inline void rotateCovariance3D(PointT& p, const Eigen::Matrix3d& R) {
  if constexpr (pcl::traits::has_field<PointT, pcl::fields::cov_zz>::value) {
    const Eigen::Matrix3d C = R * pointCovariance3D(p) * R.transpose();
    p.cov_xx = static_cast<float>(C(0, 0));
    p.cov_xy = static_cast<float>(C(0, 1));
    p.cov_xz = static_cast<float>(C(0, 2));
    p.cov_yy = static_cast<float>(C(1, 1));
    p.cov_yz = static_cast<float>(C(1, 2));
    p.cov_zz = static_cast<float>(C(2, 2));
  } else {
    (void)p;
    (void)R;
  }
}

template <typename PointT>
inline void rotateCovariance(PointT& p, const Eigen::Matrix2d& R) {
  if constexpr (pcl::traits::has_field<PointT, pcl::fields::cov_xx>::value) {
    Eigen::Matrix2d C;
    C << p.cov_xx, p.cov_xy, p.cov_xy, p.cov_yy;
    const Eigen::Matrix2d Cr = R * C * R.transpose();
    p.cov_xx = static_cast<float>(Cr(0, 0));
    p.cov_xy = static_cast<float>(Cr(0, 1));
    p.cov_yy = static_cast<float>(Cr(1, 1));
  } else {
    (void)p;
    (void)R;
  }
}

/// A usable point: finite position and covariance, covariance not negative on the diagonal.
inline bool usable(double x, double y, const Eigen::Vector3d& cov) {
  return std::isfinite(x) && std::isfinite(y) && cov.allFinite() && cov.x() >= 0 && cov.z() >= 0;
}

inline std::int32_t floorToInt(double v) {
  return static_cast<std::int32_t>(std::floor(v));
}

}  // namespace detail
}  // namespace radar_ndt

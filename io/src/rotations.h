#pragma once
// Rotation blocks as files hold them (rounded numbers): how far one is from a rotation, and the
// rotation nearest it. Shared by the trajectory readers and View-of-Delft's pose and calibration.

#include <Eigen/Core>
#include <Eigen/SVD>

namespace radar_ndt {
namespace detail {

/// max|RᵀR − I|: 0 for a rotation.
inline double orthogonalityError(const Eigen::Matrix3d& R) {
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
}

/// The rotation nearest `R` in the Frobenius norm (polar decomposition by SVD).
inline Eigen::Matrix3d nearestRotation(const Eigen::Matrix3d& R) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();
}

}  // namespace detail
}  // namespace radar_ndt

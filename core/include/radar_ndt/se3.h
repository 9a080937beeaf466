#pragma once
// SE(3) helpers shared by every layer (RadarNDT::core, header-only), for 4D radars.
// A pose is an Eigen::Isometry3d inside and a 4x4 float matrix at the PCL boundary. Small motions
// are 6-vectors (translation, rotation vector) in the frame the pose maps into: the registration
// moves a pose T = (R, t) by δ = (v, ω) to (exp(ω) R, t + v) (retractSE3), which keeps the
// translation's step a translation in metres, as PCL's transformation epsilon reads it.

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace radar_ndt {

using Pose3 = Eigen::Isometry3d;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// [v]×, the cross-product matrix: skew(v) u = v × u.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

/// exp of a rotation vector (Rodrigues), exact for every angle; identity for a zero vector.
inline Eigen::Matrix3d expSO3(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-12) return Eigen::Matrix3d::Identity() + skew(w);
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

/// The rotation vector of R (log of SO(3)), its angle in [0, π].
inline Eigen::Vector3d logSO3(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

/// (R, t) moved by δ = (v, ω): (exp(ω) R, t + v); the rotation re-orthonormalised through its
/// quaternion, so a long chain of steps stays a rotation.
inline Pose3 retractSE3(const Pose3& T, const Vector6d& d) {
  Pose3 out = Pose3::Identity();
  out.linear() = Eigen::Quaterniond(expSO3(d.tail<3>()) * T.linear()).normalized().toRotationMatrix();
  out.translation() = T.translation() + d.head<3>();
  return out;
}

/// A 4x4 matrix as a pose: its rotation block projected onto the nearest rotation (the PCL
/// boundary hands float matrices whose rotation is orthonormal to float precision only).
template <typename Derived>
inline Pose3 toPose3(const Eigen::MatrixBase<Derived>& M) {
  const Eigen::Matrix3d A = M.template topLeftCorner<3, 3>().template cast<double>();
  Pose3 T = Pose3::Identity();
  T.linear() = Eigen::Quaterniond(A).normalized().toRotationMatrix();
  T.translation() = M.template topRightCorner<3, 1>().template cast<double>();
  return T;
}

template <typename Scalar = float>
inline Eigen::Matrix<Scalar, 4, 4> toMatrix4(const Pose3& T) {
  return T.matrix().cast<Scalar>();
}

/// True when every entry is finite.
inline bool allFinite(const Pose3& T) {
  return T.matrix().allFinite();
}

}  // namespace radar_ndt

#pragma once
// SE(2) helpers shared by every layer (RadarNDT::core, header-only).
// Poses are SE(2) inside (x, y, yaw); at the PCL boundary they are 4x4 float matrices with z = 0 and
// no roll or pitch. A pose vector is (x, y, yaw) with yaw in radians, counter-clockwise about +z.

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace radar_ndt {

using Pose2 = Eigen::Vector3d;  ///< (x, y, yaw)

/// π, as a constant: the POSIX macro for it is not standard C++.
constexpr double kPi = 3.14159265358979323846;

/// Wraps an angle to (-pi, pi].
inline double normalizeAngle(double a) {
  a = std::remainder(a, 2.0 * kPi);  // [-pi, pi]
  return a <= -kPi ? a + 2.0 * kPi : a;
}

template <typename Scalar = double>
inline Eigen::Transform<Scalar, 2, Eigen::Isometry> toIsometry2(const Pose2& p) {
  Eigen::Transform<Scalar, 2, Eigen::Isometry> T = Eigen::Transform<Scalar, 2, Eigen::Isometry>::Identity();
  T.linear() = Eigen::Rotation2D<Scalar>(static_cast<Scalar>(p.z())).toRotationMatrix();
  T.translation() << static_cast<Scalar>(p.x()), static_cast<Scalar>(p.y());
  return T;
}

template <typename Scalar>
inline Pose2 toPose2(const Eigen::Transform<Scalar, 2, Eigen::Isometry>& T) {
  return Pose2(T.translation().x(), T.translation().y(),
               std::atan2(static_cast<double>(T.linear()(1, 0)), static_cast<double>(T.linear()(0, 0))));
}

/// 4x4 homogeneous matrix (the PCL boundary): rotation about z, translation in x-y.
template <typename Scalar = float>
inline Eigen::Matrix<Scalar, 4, 4> toMatrix4(const Pose2& p) {
  Eigen::Matrix<Scalar, 4, 4> M = Eigen::Matrix<Scalar, 4, 4>::Identity();
  const double c = std::cos(p.z()), s = std::sin(p.z());
  M(0, 0) = static_cast<Scalar>(c);
  M(0, 1) = static_cast<Scalar>(-s);
  M(1, 0) = static_cast<Scalar>(s);
  M(1, 1) = static_cast<Scalar>(c);
  M(0, 3) = static_cast<Scalar>(p.x());
  M(1, 3) = static_cast<Scalar>(p.y());
  return M;
}

/// Projects a 4x4 (or 3D) transform onto the plane: x, y and the yaw of the rotated x axis.
/// z, roll and pitch are dropped.
template <typename Derived>
inline Pose2 toPose2(const Eigen::MatrixBase<Derived>& M) {
  static_assert(Derived::RowsAtCompileTime == 4 && Derived::ColsAtCompileTime == 4, "4x4 matrix expected");
  return Pose2(static_cast<double>(M(0, 3)), static_cast<double>(M(1, 3)),
               std::atan2(static_cast<double>(M(1, 0)), static_cast<double>(M(0, 0))));
}

/// a ⊕ b: the pose b (expressed in a's frame) moved into a's parent frame.
inline Pose2 compose(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.z()), s = std::sin(a.z());
  return Pose2(a.x() + c * b.x() - s * b.y(), a.y() + s * b.x() + c * b.y(), normalizeAngle(a.z() + b.z()));
}

/// a⁻¹
inline Pose2 inverse(const Pose2& a) {
  const double c = std::cos(a.z()), s = std::sin(a.z());
  return Pose2(-c * a.x() - s * a.y(), s * a.x() - c * a.y(), normalizeAngle(-a.z()));
}

/// a⁻¹ ⊕ b: the pose b seen from a (the relative motion from a to b).
inline Pose2 between(const Pose2& a, const Pose2& b) {
  return compose(inverse(a), b);
}

/// The pose a fraction `u` of the way from `a` to `b`: position along the straight line, heading
/// along the shorter arc (u = 0: a, u = 1: b). The one interpolation of planar poses (the
/// simulator's trajectories); a Trajectory's poses at a time are Trajectory::poseAt's, the same
/// interpolation in 3D.
inline Pose2 interpolate(const Pose2& a, const Pose2& b, double u) {
  return Pose2(a.x() + u * (b.x() - a.x()), a.y() + u * (b.y() - a.y()),
               normalizeAngle(a.z() + u * normalizeAngle(b.z() - a.z())));
}

/// Planar 3D isometry (z = 0, rotation about z) from an SE(2) pose.
inline Eigen::Isometry3d toIsometry3(const Pose2& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(p.z(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() << p.x(), p.y(), 0.0;
  return T;
}

/// The SE(2) part of a 3D isometry (x, y, yaw of the rotated x axis).
inline Pose2 toPose2(const Eigen::Isometry3d& T) {
  return toPose2(T.matrix());
}

/// The motion over `dt` seconds at constant body velocity v = (vx, vy, ω) (vehicle frame): the pose
/// of the vehicle at t + dt in its frame at t, exp(v·dt) on SE(2) (exact along the arc).
namespace detail {
/// sin θ / θ and (1 − cos θ) / θ, by series near 0: the entries of SE(2)'s V(θ) = [a −b; b a].
inline void expCoefficients(double th, double& a, double& b) {
  if (std::abs(th) < 1e-6) {
    a = 1.0 - th * th / 6.0;
    b = 0.5 * th;
  } else {
    a = std::sin(th) / th;
    b = (1.0 - std::cos(th)) / th;
  }
}
}  // namespace detail

inline Pose2 integrateVelocity(const Eigen::Vector3d& v, double dt) {
  const double th = v.z() * dt;
  double a, b;
  detail::expCoefficients(th, a, b);
  return Pose2((a * v.x() - b * v.y()) * dt, (b * v.x() + a * v.y()) * dt, th);
}

/// The constant body velocity (vx, vy, ω) that moves by `motion` in `dt` seconds (dt > 0): the
/// inverse of integrateVelocity, log(motion) / dt on SE(2).
inline Eigen::Vector3d velocityOf(const Pose2& motion, double dt) {
  const double th = motion.z();
  double a, b;
  detail::expCoefficients(th, a, b);
  // [a −b; b a]⁻¹ = [a b; −b a] / (a² + b²)
  const double d = a * a + b * b;
  return Eigen::Vector3d((a * motion.x() + b * motion.y()) / (d * dt), (-b * motion.x() + a * motion.y()) / (d * dt),
                         th / dt);
}

}  // namespace radar_ndt

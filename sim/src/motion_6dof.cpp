#include "radar_ndt/sim/motion_6dof.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "radar_ndt/se2.h"
#include "radar_ndt/se3.h"

#include "sim_random.h"

namespace radar_ndt {
namespace sim {

namespace {

/// The cumulative cubic B-spline basis B̃1..B̃3 at u in [0, 1).
Eigen::Vector3d cumulativeBasis(double u) {
  const double u2 = u * u, u3 = u2 * u;
  return Eigen::Vector3d((5 + 3 * u - 3 * u2 + u3) / 6, (1 + 3 * u + 3 * u2 - 2 * u3) / 6, u3 / 6);
}

constexpr double kStill = 2.0;  // s the spline holds the first pose before the file's motion
constexpr double kDiff = 1e-3;  // s: the central differences' step (the spline is C²)

}  // namespace

Motion6Dof::Motion6Dof(const Trajectory& trajectory, double knot_spacing) : dt_(knot_spacing) {
  if (!trajectory.hasStamps() || trajectory.size() < 4)
    throw std::invalid_argument("a 6-DoF motion needs a trajectory with stamps and at least 4 poses");
  if (!(knot_spacing > 0)) throw std::invalid_argument("knot spacing must be positive");
  // A still start (the IMU's bias is taken there, as a real recording starts), then the file.
  const double first = trajectory.stamps.front(), last = trajectory.stamps.back();
  t0_ = first - kStill - dt_;
  for (double t = t0_; t <= last + 1e-9; t += dt_) {
    Eigen::Isometry3d p;
    if (!trajectory.poseAt(std::max(t, first), &p)) trajectory.poseAt(first, &p);
    knots_.push_back(p);
  }
  if (knots_.size() < 4) throw std::invalid_argument("the trajectory is shorter than three knot spacings");
}

Eigen::Isometry3d Motion6Dof::pose(double t) const {
  const double s = std::clamp((t - t0_) / dt_, 1.0, static_cast<double>(knots_.size()) - 2.0 - 1e-9);
  const std::size_t i = static_cast<std::size_t>(std::floor(s));
  const Eigen::Vector3d b = cumulativeBasis(s - static_cast<double>(i));
  Eigen::Vector3d p = knots_[i - 1].translation();
  Eigen::Matrix3d R = knots_[i - 1].linear();
  for (int j = 1; j <= 3; ++j) {
    const Eigen::Isometry3d &a = knots_[i - 2 + j], &c = knots_[i - 1 + j];
    p += b[j - 1] * (c.translation() - a.translation());
    R = R * expSO3(b[j - 1] * logSO3(a.linear().transpose() * c.linear()));
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = p;
  return T;
}

Eigen::Vector3d Motion6Dof::velocity(double t) const {
  return (pose(t + kDiff).translation() - pose(t - kDiff).translation()) / (2 * kDiff);
}

Eigen::Vector3d Motion6Dof::acceleration(double t) const {
  return (pose(t + kDiff).translation() - 2 * pose(t).translation() + pose(t - kDiff).translation()) / (kDiff * kDiff);
}

Eigen::Vector3d Motion6Dof::angularVelocity(double t) const {
  return logSO3(pose(t - kDiff).linear().transpose() * pose(t + kDiff).linear()) / (2 * kDiff);
}

double Motion6Dof::length() const {
  double s = 0;
  for (double t = start() + 0.1; t <= end(); t += 0.1)
    s += (pose(t).translation() - pose(t - 0.1).translation()).norm();
  return s;
}

void Imu6Options::validate() const {
  checkFields(*this, "Imu6Options");
}

Imu6Options imu6Preset(const std::string& grade) {
  Imu6Options o;
  if (grade == "none") return o;
  if (grade == "mems") {
    // ADIS16448 datasheet: angle random walk 0.66°/√h, in-run bias stability 14.5°/h, velocity
    // random walk 0.11 m/s/√h, accelerometer bias stability 0.25 mg; a turn-on bias of 0.2°/s and
    // 5 mg after the factory's calibration. The in-run stability as a random walk over 100 s.
    o.gyro_noise_density = 0.66 * kPi / 180 / 60;
    o.gyro_turn_on_bias = 0.2 * kPi / 180;
    o.gyro_bias_walk = 14.5 * kPi / 180 / 3600 / 10;
    o.accel_noise_density = 0.11 / 60;
    o.accel_turn_on_bias = 5e-3 * 9.81;
    o.accel_bias_walk = 0.25e-3 * 9.81 / 10;
    return o;
  }
  if (grade == "navigation") {
    // A fibre-optic navigation grade: 0.005°/√h, 0.01°/h stability, 0.03 m/s/√h, 25 µg.
    o.gyro_noise_density = 0.005 * kPi / 180 / 60;
    o.gyro_turn_on_bias = 0.01 * kPi / 180 / 3600;
    o.gyro_bias_walk = 0.01 * kPi / 180 / 3600 / 10;
    o.accel_noise_density = 0.03 / 60;
    o.accel_turn_on_bias = 25e-6 * 9.81;
    o.accel_bias_walk = 25e-6 * 9.81 / 10;
    return o;
  }
  throw std::invalid_argument("unknown IMU grade '" + grade + "' (none, mems, navigation)");
}

std::vector<ImuSample> simulateImu6(const Motion6Dof& motion, const Imu6Options& o, std::uint64_t seed) {
  o.validate();
  Random rng(seed, 0x1a06);
  auto draw = [&](double s) { return Eigen::Vector3d(s * rng.normal(), s * rng.normal(), s * rng.normal()); };
  Eigen::Vector3d bg = draw(o.gyro_turn_on_bias), ba = draw(o.accel_turn_on_bias);
  const double dt = 1.0 / o.rate;
  std::vector<ImuSample> out;
  for (double t = motion.start(); t <= motion.end(); t += dt) {
    const Eigen::Matrix3d R = motion.pose(t).linear();
    ImuSample s;
    s.t = t;
    s.gyro = motion.angularVelocity(t) + bg + draw(o.gyro_noise_density / std::sqrt(dt));
    s.accel = R.transpose() * (motion.acceleration(t) + Eigen::Vector3d(0, 0, o.gravity)) + ba +
              draw(o.accel_noise_density / std::sqrt(dt));
    out.push_back(s);
    bg += draw(o.gyro_bias_walk * std::sqrt(dt));
    ba += draw(o.accel_bias_walk * std::sqrt(dt));
  }
  return out;
}

namespace {

/// The path every 0.5 m, on a 2 m grid: whether a point lies clear of every part of it.
class PathClearance {
 public:
  explicit PathClearance(const Motion6Dof& motion) {
    for (double t = motion.start(); t <= motion.end(); t += 0.05)
      if (poses.empty() || (motion.pose(t).translation() - poses.back().translation()).norm() > 0.5)
        poses.push_back(motion.pose(t));
    for (const auto& p : poses) cells_.emplace(key(p.translation().x(), p.translation().y()), p.translation());
  }
  /// True when no point of the path lies within `margin` (m, horizontally) of `c`.
  bool clear(const Eigen::Vector3d& c, double margin) const {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy) {
        auto range = cells_.equal_range(key(c.x() + 2 * dx, c.y() + 2 * dy));
        for (auto it = range.first; it != range.second; ++it)
          if ((it->second.head<2>() - c.head<2>()).norm() < margin) return false;
      }
    return true;
  }
  std::vector<Eigen::Isometry3d> poses;

 private:
  /// The 2 m cell's key: both indices as unsigned (a negative index wraps, well defined), x's in the
  /// high half.
  static std::uint64_t key(double x, double y) {
    const auto ix = static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(x / 2)));
    const auto iy = static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(y / 2)));
    return (ix << 32) ^ (iy & 0xffffffffULL);
  }
  std::unordered_multimap<std::uint64_t, Eigen::Vector3d> cells_;
};

/// The path's points, then on straight past its end along its last heading, every 0.5 m for
/// `beyond` m: the world goes on as far as the radar looks ahead (a street, a corridor), or a rig
/// that stops at the end would face nothing but false alarms. After the path's own points, so
/// those draw the same random numbers as without. A path of one point gets none.
std::vector<Eigen::Vector3d> centresPastTheEnd(const std::vector<Eigen::Isometry3d>& poses, double beyond) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : poses) out.push_back(p.translation());
  if (poses.size() < 2) return out;
  Eigen::Vector3d heading = out.back() - out[out.size() - 2];
  heading.z() = 0;
  const Eigen::Vector3d end = out.back();
  for (double d = 0.5; d <= beyond; d += 0.5)
    out.push_back(heading.norm() < 1e-9 ? end : Eigen::Vector3d(end + d * heading.normalized()));
  return out;
}

}  // namespace

World3D worldAlongPath(const Motion6Dof& motion, bool car, std::uint64_t seed) {
  Random rng(seed, car ? 0xca4 : 0x4a4d);
  World3D w;
  const PathClearance path(motion);
  auto clear = [&](const Eigen::Vector3d& c, double margin) { return path.clear(c, margin); };
  const double below = car ? 1.5 : 1.2, above = car ? 0 : 1.6;
  const std::vector<Eigen::Vector3d> centres = centresPastTheEnd(path.poses, car ? 100.0 : 15.0);
  const std::size_t n = path.poses.size();
  double along = 0;
  for (std::size_t k = 0; k < centres.size(); ++k) {
    const Eigen::Vector3d c = centres[k];
    // A path of one pose (a motion that never moves) has no direction: no world along it.
    const Eigen::Vector3d fwd = k + 1 < n ? Eigen::Vector3d(centres[k + 1] - c)
                                : k > 0   ? Eigen::Vector3d(c - centres[k - 1])
                                          : Eigen::Vector3d::Zero();
    Eigen::Vector3d side(-fwd.y(), fwd.x(), 0);
    if (side.norm() < 1e-9) continue;
    side.normalize();
    along += 0.5;
    // The floor (and ceiling) under this stretch: a 3 m tile at the path's height.
    const double floor_z = c.z() - below;
    if (k % 4 == 0) {
      w.patches.push_back({{c.x() - 1.5, c.y() - 1.5, floor_z}, {3, 0, 0}, {0, 3, 0}, car ? -5.f : -8.f});
      if (!car) w.patches.push_back({{c.x() - 1.5, c.y() - 1.5, c.z() + above}, {3, 0, 0}, {0, 3, 0}, -8.f});
    }
    for (int s : {-1, 1}) {
      const double offset = car ? rng.uniform(8, 15) : rng.uniform(2.5, 7.0);
      const double size = car ? rng.uniform(0.8, 2.0) : 0.35, height = car ? rng.uniform(6, 20) : above + below;
      if (rng.chance(car ? 0.3 : 0.15)) continue;  // a gap, a door
      const Eigen::Vector3d q = c + s * offset * side;
      if (!clear(q, 1.0 + 0.7 * size)) continue;
      w.boxes.push_back({{q.x() - size / 2, q.y() - size / 2, floor_z},
                         {q.x() + size / 2, q.y() + size / 2, floor_z + height},
                         car ? 15.f : 12.f});
      if (car && std::fmod(along, 20.0) < 0.5) {  // a pole every 20 m; a parked car now and then
        const Eigen::Vector3d pole = c + s * 5.0 * side;
        if (clear(pole, 1.0)) w.poles.push_back({pole.head<2>(), 0.15, 5.0, 5.f});
      }
      if (car && rng.chance(0.05)) {
        const Eigen::Vector3d pc = c + s * 3.5 * side;
        if (clear(pc, 2.0))
          w.boxes.push_back({{pc.x() - 1.0, pc.y() - 1.0, floor_z}, {pc.x() + 1.0, pc.y() + 1.0, floor_z + 1.5}, 10.f});
      }
      if (!car && rng.chance(0.1)) {  // a pillar or cabinet inside the corridor's edge
        const Eigen::Vector3d pc = c + s * (offset - 0.4) * side;
        if (clear(pc, 0.9))
          w.boxes.push_back({{pc.x() - 0.25, pc.y() - 0.25, floor_z},
                             {pc.x() + 0.25, pc.y() + 0.25, floor_z + rng.uniform(1.0, 2.0)},
                             8.f});
      }
    }
  }
  return w;
}

namespace {

/// The part of `world` within `radius` (horizontally) of `c`: what one scan can see.
World3D nearby(const World3D& world, const Eigen::Vector3d& c, double radius) {
  World3D out;
  for (const Box3& b : world.boxes) {
    const Eigen::Vector3d m = 0.5 * (b.min + b.max);
    if ((m.head<2>() - c.head<2>()).norm() < radius + 0.5 * (b.max - b.min).head<2>().norm()) out.boxes.push_back(b);
  }
  for (const Pole3& p : world.poles)
    if ((p.xy - c.head<2>()).norm() < radius) out.poles.push_back(p);
  for (const Patch3& p : world.patches) {
    const Eigen::Vector3d m = p.origin + 0.5 * (p.u + p.v);
    if ((m.head<2>() - c.head<2>()).norm() < radius + 0.5 * (p.u + p.v).norm()) out.patches.push_back(p);
  }
  return out;
}

}  // namespace

Radar4DSequence simulateRadar4DSequence(const Motion6Dof& motion, const World3D& world, const Radar4DModel& model,
                                        double rate, const Imu6Options& imu, std::uint64_t seed,
                                        const Eigen::Isometry3d& mounting) {
  if (!(rate > 0)) throw std::invalid_argument("the radar's rate must be positive");
  Radar4DSequence seq;
  seq.imu = simulateImu6(motion, imu, seed);
  std::uint64_t k = 0;
  for (double t = motion.start() + 0.5 / rate; t <= motion.end(); t += 1.0 / rate, ++k) {
    const Eigen::Isometry3d T = motion.pose(t);
    const World3D local = nearby(world, T.translation(), model.max_range);
    // The radar's own velocity: the body's plus the lever arm's turn, ω × t in the body, in the world.
    const Eigen::Vector3d v = motion.velocity(t) + T.linear() * motion.angularVelocity(t).cross(mounting.translation());
    seq.scans.push_back(simulateScan4D(local, T * mounting, v, model, seed, k));
    seq.stamps.push_back(t);
    seq.truth.stamps.push_back(t);
    seq.truth.poses.push_back(T);
  }
  return seq;
}

}  // namespace sim
}  // namespace radar_ndt

#include "radar_ndt/sim/synthetic_scan.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace radar_ndt {
namespace {

struct Segment {
  Eigen::Vector2d a, b;
  double length() const { return (b - a).norm(); }
};

/// A world of straight structure (walls, building outlines, fences), poles and curved kerbs,
/// as line segments; poles are tiny squares, arcs are chains of short segments.
std::vector<Segment> makeWorld(const SyntheticScanOptions& o, std::mt19937& rng) {
  std::uniform_real_distribution<double> U(-o.extent, o.extent), U01(0, 1);
  std::vector<Segment> w;
  const auto add = [&](Eigen::Vector2d a, Eigen::Vector2d b) { w.push_back({a, b}); };
  for (int i = 0; i < 12; ++i) {  // building outlines (rectangles)
    const Eigen::Vector2d c(U(rng), U(rng));
    const double yaw = U01(rng) * kPi, sx = 4 + 14 * U01(rng), sy = 4 + 10 * U01(rng);
    const Eigen::Rotation2Dd R(yaw);
    const Eigen::Vector2d k[4] = {c + R * Eigen::Vector2d(-sx, -sy), c + R * Eigen::Vector2d(sx, -sy),
                                  c + R * Eigen::Vector2d(sx, sy), c + R * Eigen::Vector2d(-sx, sy)};
    for (int j = 0; j < 4; ++j) add(k[j], k[(j + 1) % 4]);
  }
  for (int i = 0; i < 14; ++i) {  // free walls and fences
    const Eigen::Vector2d a(U(rng), U(rng));
    const double yaw = U01(rng) * 2 * kPi, len = 5 + 25 * U01(rng);
    add(a, a + len * Eigen::Vector2d(std::cos(yaw), std::sin(yaw)));
  }
  for (int i = 0; i < 40; ++i) {  // poles
    const Eigen::Vector2d c(U(rng), U(rng));
    const double r = 0.15;
    add(c + Eigen::Vector2d(-r, -r), c + Eigen::Vector2d(r, r));
    add(c + Eigen::Vector2d(-r, r), c + Eigen::Vector2d(r, -r));
  }
  for (int i = 0; i < 4; ++i) {  // curved kerbs
    const Eigen::Vector2d c(U(rng), U(rng));
    const double r = 8 + 20 * U01(rng), a0 = U01(rng) * 2 * kPi;
    for (int j = 0; j < 16; ++j) {
      const double t0 = a0 + 0.1 * j, t1 = a0 + 0.1 * (j + 1);
      add(c + r * Eigen::Vector2d(std::cos(t0), std::sin(t0)), c + r * Eigen::Vector2d(std::cos(t1), std::sin(t1)));
    }
  }
  return w;
}

/// Samples `n` points of the world seen from `pose` (world frame), expressed in that frame.
void sampleScan(const std::vector<Segment>& world, const Pose2& pose, const SyntheticScanOptions& o, std::mt19937& rng,
                pcl::PointCloud<PointRadar>& out) {
  std::vector<double> cum;
  double total = 0;
  for (const auto& s : world) cum.push_back(total += s.length());
  std::uniform_real_distribution<double> U01(0, 1), U(-o.extent - 5, o.extent + 5);
  std::uniform_real_distribution<float> power(0.5f, 1.0f), clutter_power(0.02f, o.clutter_power_max);
  std::normal_distribution<double> N(0, 1);
  const auto n_clutter = static_cast<std::size_t>(std::llround(o.clutter_fraction * static_cast<double>(o.points)));
  const Eigen::Isometry2d world_to_scan = toIsometry2(inverse(pose));
  const float var = static_cast<float>(o.noise_std * o.noise_std);
  out.clear();
  out.reserve(o.points);
  for (std::size_t i = 0; i < o.points; ++i) {
    Eigen::Vector2d p;
    float pw;
    if (i < n_clutter) {
      p = Eigen::Vector2d(U(rng), U(rng));
      pw = clutter_power(rng);
    } else {
      const double u = U01(rng) * total;
      const std::size_t k = static_cast<std::size_t>(std::lower_bound(cum.begin(), cum.end(), u) - cum.begin());
      const Segment& s = world[std::min(k, world.size() - 1)];
      p = s.a + U01(rng) * (s.b - s.a);
      pw = power(rng);
    }
    const Eigen::Vector2d q = world_to_scan * p + o.noise_std * Eigen::Vector2d(N(rng), N(rng));
    PointRadar pt(static_cast<float>(q.x()), static_cast<float>(q.y()), 0.0f, pw);
    pt.cov_xx = pt.cov_yy = var;
    out.push_back(pt);
  }
  out.width = static_cast<std::uint32_t>(out.size());
  out.height = 1;
  out.is_dense = true;
}

}  // namespace

SyntheticScanPair makeSyntheticScanPair(const SyntheticScanOptions& o) {
  o.validate();
  std::mt19937 rng(o.seed);
  const std::vector<Segment> world = makeWorld(o, rng);
  std::uniform_real_distribution<double> U01(0, 1);
  SyntheticScanPair pair;
  const double r = o.max_translation * U01(rng), dir = 2 * kPi * U01(rng);
  const double yaw = (2 * U01(rng) - 1) * o.max_rotation_deg * kPi / 180.0;
  pair.source_in_target = Pose2(r * std::cos(dir), r * std::sin(dir), yaw);
  sampleScan(world, Pose2::Zero(), o, rng, pair.target);
  sampleScan(world, pair.source_in_target, o, rng, pair.source);
  return pair;
}

}  // namespace radar_ndt

// radar_sim, part 1: the trajectory, the materials, the generated world and ray casting.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "radar_ndt/sim/radar_sim.h"
#include "sim_random.h"

namespace radar_ndt {
namespace sim {
namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

std::int64_t cellKey(long ix, long iy) {
  // Packed as unsigned: shifting a negative signed value is undefined before C++20 (UBSan).
  const std::uint64_t hi = static_cast<std::uint32_t>(ix), lo = static_cast<std::uint32_t>(iy);
  return static_cast<std::int64_t>((hi << 32) | lo);
}

}  // namespace

// ---- trajectory -------------------------------------------------------------------------------

SimTrajectory::SimTrajectory(const Trajectory& trajectory, double period) {
  if (trajectory.empty()) throw std::invalid_argument("radar_sim: the trajectory is empty");
  std::vector<double> stamps;
  std::vector<Pose2> poses;
  for (std::size_t k = 0; k < trajectory.size(); ++k) {
    stamps.push_back(trajectory.hasStamps() ? trajectory.stamps[k] - trajectory.stamps[0] : period * k);
    poses.push_back(toPose2(trajectory.poses[k]));
  }
  *this = SimTrajectory(std::move(stamps), std::move(poses));
}

SimTrajectory::SimTrajectory(std::vector<double> stamps, std::vector<Pose2> poses)
    : stamps_(std::move(stamps)), poses_(std::move(poses)) {
  if (poses_.size() < 2 || stamps_.size() != poses_.size())
    throw std::invalid_argument("radar_sim: a trajectory needs at least 2 poses with one stamp each");
  for (std::size_t k = 1; k < stamps_.size(); ++k)
    if (!(stamps_[k] > stamps_[k - 1])) throw std::invalid_argument("radar_sim: trajectory stamps must increase");
  arc_.assign(poses_.size(), 0.0);
  for (std::size_t k = 1; k < poses_.size(); ++k)
    arc_[k] = arc_[k - 1] + (poses_[k].head<2>() - poses_[k - 1].head<2>()).norm();
  // Direction of travel at each end: the nearest segment that moves (else the pose's heading).
  auto direction = [&](std::size_t j) {
    return std::atan2(poses_[j + 1].y() - poses_[j].y(), poses_[j + 1].x() - poses_[j].x());
  };
  start_heading_ = poses_.front().z();
  end_heading_ = poses_.back().z();
  for (std::size_t j = 0; j + 1 < poses_.size(); ++j)
    if (arc_[j + 1] - arc_[j] > 0.05) {
      start_heading_ = direction(j);
      break;
    }
  for (std::size_t j = poses_.size() - 1; j > 0; --j)
    if (arc_[j] - arc_[j - 1] > 0.05) {
      end_heading_ = direction(j - 1);
      break;
    }
}

std::size_t SimTrajectory::segment(double t) const {
  const auto it = std::upper_bound(stamps_.begin(), stamps_.end(), t);
  std::size_t k = static_cast<std::size_t>(it - stamps_.begin());
  k = k == 0 ? 0 : k - 1;
  return std::min(k, stamps_.size() - 2);
}

Pose2 SimTrajectory::at(double t) const {
  t = std::min(std::max(t, stamps_.front()), stamps_.back());
  const std::size_t k = segment(t);
  return interpolate(poses_[k], poses_[k + 1], (t - stamps_[k]) / (stamps_[k + 1] - stamps_[k]));
}

Eigen::Vector3d SimTrajectory::velocity(double t) const {
  const std::size_t k = segment(std::min(std::max(t, stamps_.front()), stamps_.back()));
  const double dt = stamps_[k + 1] - stamps_[k];
  const Pose2 d = between(poses_[k], poses_[k + 1]);
  const Pose2 here = at(t);
  // The segment's displacement expressed in the frame at t (a small correction for the heading
  // turned so far within the segment).
  const double dyaw = normalizeAngle(here.z() - poses_[k].z());
  const double c = std::cos(dyaw), s = std::sin(dyaw);
  return Eigen::Vector3d((c * d.x() + s * d.y()) / dt, (-s * d.x() + c * d.y()) / dt, d.z() / dt);
}

double SimTrajectory::arcAt(double t) const {
  t = std::min(std::max(t, stamps_.front()), stamps_.back());
  const std::size_t k = segment(t);
  const double u = (t - stamps_[k]) / (stamps_[k + 1] - stamps_[k]);
  return arc_[k] + u * (arc_[k + 1] - arc_[k]);
}

Pose2 SimTrajectory::atArc(double s) const {
  // Beyond the ends: straight on along the first / last direction of travel (the world is
  // generated a little past both ends of the path).
  const double extra = s < 0.0 ? s : (s > arc_.back() ? s - arc_.back() : 0.0);
  s = std::min(std::max(s, 0.0), arc_.back());
  auto it = std::upper_bound(arc_.begin(), arc_.end(), s);
  std::size_t k = static_cast<std::size_t>(it - arc_.begin());
  k = std::min(k == 0 ? 0 : k - 1, arc_.size() - 2);
  // Standstill segments (zero length) are skipped for the heading: it follows the direction of travel.
  const double len = arc_[k + 1] - arc_[k];
  const double u = len > 1e-9 ? (s - arc_[k]) / len : 0.0;
  const Pose2& a = poses_[k];
  const Pose2& b = poses_[k + 1];
  double heading = len > 0.05 ? std::atan2(b.y() - a.y(), b.x() - a.x()) : a.z();
  if (extra != 0.0) {
    const Pose2& end = extra < 0.0 ? poses_.front() : poses_.back();
    const double h = extra < 0.0 ? start_heading_ : end_heading_;
    return Pose2(end.x() + extra * std::cos(h), end.y() + extra * std::sin(h), h);
  }
  return Pose2(a.x() + u * (b.x() - a.x()), a.y() + u * (b.y() - a.y()), heading);
}

SimTrajectory builtinDrive(double duration, double period) {
  if (!(duration > period) || !(period > 0))
    throw std::invalid_argument("radar_sim: the built-in drive needs duration > period > 0");
  // A repeating 60 s pattern of (seconds, target speed m/s, yaw rate rad/s).
  struct Phase {
    double seconds, speed, yaw_rate;
  };
  static const Phase kPattern[] = {{6, 8, 0},         {14, 12, 0},   {7, 6, kPi / 14}, {12, 11, 0},
                                   {6, 5, -kPi / 12}, {5, 10, 0.04}, {4, 0, 0},        {6, 9, 0}};
  double pattern_length = 0;
  for (const Phase& p : kPattern) pattern_length += p.seconds;
  constexpr double kStep = 0.01, kAccel = 2.0;
  std::vector<double> stamps;
  std::vector<Pose2> poses;
  Pose2 pose(0, 0, 0);
  double v = 0, next = 0;
  for (double t = 0; t <= duration + 1e-9; t += kStep) {
    if (t + 1e-9 >= next) {
      stamps.push_back(next);
      poses.push_back(pose);
      next += period;
    }
    double u = std::fmod(t, pattern_length);
    const Phase* phase = &kPattern[0];
    for (const Phase& p : kPattern) {
      phase = &p;
      if (u < p.seconds) break;
      u -= p.seconds;
    }
    v += std::max(-kAccel * kStep, std::min(kAccel * kStep, phase->speed - v));
    const double w = phase->speed > 0 ? phase->yaw_rate * v / phase->speed : 0.0;
    pose.x() += v * std::cos(pose.z()) * kStep;
    pose.y() += v * std::sin(pose.z()) * kStep;
    pose.z() = normalizeAngle(pose.z() + w * kStep);
  }
  return SimTrajectory(std::move(stamps), std::move(poses));
}

// ---- materials --------------------------------------------------------------------------------

const char* toString(Material m) {
  switch (m) {
    case Material::Building: return "building";
    case Material::Car: return "car";
    case Material::Bus: return "bus";
    case Material::Pole: return "pole";
    case Material::Trunk: return "trunk";
    case Material::Crown: return "crown";
    case Material::Fence: return "fence";
    case Material::Hedge: return "hedge";
    case Material::Wall: return "wall";
  }
  return "?";
}

const MaterialModel& materialModel(Material m) {
  // reflect_db, transmission, depth, incidence_exp, rcs_dbsm
  static const MaterialModel kModels[] = {
      {0.0, 0.0, 0.6, 1.0, 15.0},    // Building: brick and glass facades, windows and recesses
      {2.0, 0.35, 0.8, 0.5, 8.0},    // Car: corner reflectors; the roof-mounted radar partly sees over it
      {4.0, 0.0, 0.8, 0.5, 14.0},    // Bus
      {1.0, 0.0, 0.15, 0.0, 5.0},    // Pole: metal cylinder
      {-5.0, 0.0, 0.2, 0.0, 0.0},    // Trunk
      {-13.0, 0.6, 2.5, 0.0, -5.0},  // Crown: leaves and branches, mostly transparent
      {-4.0, 0.5, 0.2, 0.3, 2.0},    // Fence: metal railings
      {-9.0, 0.25, 1.2, 0.0, -3.0},  // Hedge
      {-2.0, 0.0, 0.3, 1.0, 8.0},    // Wall: low garden walls and kerbstones
  };
  return kModels[static_cast<int>(m)];
}

// ---- world generation --------------------------------------------------------------------------

/// Distance from a point to the nearest sampled path position (for keeping the road clear).
class PathClearance {
 public:
  explicit PathClearance(const SimTrajectory& path) {
    const double L = path.length();
    for (double s = 0; s <= L + 1e-9; s += 1.0) add(path.atArc(s).head<2>());
    for (const Pose2& p : path.poses()) add(p.head<2>());
  }
  double distance(const Eigen::Vector2d& q) const {
    const long ix = static_cast<long>(std::floor(q.x() / kCell)), iy = static_cast<long>(std::floor(q.y() / kCell));
    double best = kCell;
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy) {
        const auto it = grid_.find(cellKey(ix + dx, iy + dy));
        if (it == grid_.end()) continue;
        for (const auto& p : it->second) best = std::min(best, (p - q).norm());
      }
    return best;
  }

 private:
  static constexpr double kCell = 12.0;
  void add(const Eigen::Vector2d& p) {
    grid_[cellKey(static_cast<long>(std::floor(p.x() / kCell)), static_cast<long>(std::floor(p.y() / kCell)))]
        .push_back(p);
  }
  std::unordered_map<std::int64_t, std::vector<Eigen::Vector2d>> grid_;
};

namespace {

Eigen::Vector2d offsetPoint(const SimTrajectory& path, double s, double lateral) {
  const Pose2 p = path.atArc(s);
  return Eigen::Vector2d(p.x() - lateral * std::sin(p.z()), p.y() + lateral * std::cos(p.z()));
}

}  // namespace

World World::generate(const SimTrajectory& path, const WorldOptions& o) {
  World w;
  w.path_ = &path;
  if (o.mirror != 0.0 && o.mirror != 1.0)
    throw std::invalid_argument("radar_sim: the world setting mirror must be 0 or 1");
  Random rng(o.seed, 0x5eed);
  // Mirrored: every lateral offset and every orientation relative to the path is negated, with the
  // same random draws, so a seed gives the mirror image of its world (exact on a straight path).
  const double mirror = o.mirror != 0.0 ? -1.0 : 1.0;
  auto mirroredAngle = [&](double s, double a) { return mirror > 0 ? a : 2.0 * path.atArc(s).z() - a; };
  w.clearance_ = std::make_shared<const PathClearance>(path);
  const PathClearance& clearance = *w.clearance_;
  const double L = path.length();
  constexpr double kClear = 2.2;  // m: nothing closer than this to any part of the path

  auto clear = [&](const Eigen::Vector2d& p, double need) { return clearance.distance(p) >= need; };
  auto addSegment = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b, Material m, double need) {
    if ((b - a).norm() < 0.2) return;
    if (!clear(a, need) || !clear(b, need) || !clear(0.5 * (a + b), need)) return;
    w.segments_.push_back({a, b, m});
  };
  auto addBox = [&](const Eigen::Vector2d& c, double heading, double length, double width, Material m) {
    // Mirrored, v flips too: the corners come in mirrored order, so each side keeps its index (and
    // with it its ghost draw).
    const Eigen::Vector2d u(std::cos(heading), std::sin(heading)), v = mirror * Eigen::Vector2d(-u.y(), u.x());
    const Eigen::Vector2d q[4] = {c + 0.5 * length * u + 0.5 * width * v, c - 0.5 * length * u + 0.5 * width * v,
                                  c - 0.5 * length * u - 0.5 * width * v, c + 0.5 * length * u - 0.5 * width * v};
    for (const auto& p : q)
      if (!clear(p, kClear)) return;
    for (int i = 0; i < 4; ++i) w.segments_.push_back({q[i], q[(i + 1) % 4], m});
  };
  auto addCircle = [&](const Eigen::Vector2d& c, double r, Material m, double need) {
    if (!clear(c, need + r)) return;
    w.circles_.push_back({c, r, m});
  };

  constexpr double kBlock = 30.0;
  for (double s0 = -40.0; s0 < L + 40.0; s0 += kBlock) {
    for (int kerb : {+1, -1}) {
      const double side = mirror * kerb;  // +1: left of the path
      const double half = rng.uniform(o.road_half_width_min, o.road_half_width_max);
      const bool facade = rng.chance(o.building_probability);
      if (facade) {
        // A facade: segments of 3–9 m with small set-backs, recesses and an occasional gap.
        const double setback = half + rng.uniform(1.5, 7.0);
        double s = s0;
        while (s < s0 + kBlock) {
          const double len = rng.uniform(3.0, 9.0);
          const double e = std::min(s + len, s0 + kBlock);
          if (!rng.chance(o.facade_gap_probability)) {
            const double off = side * (setback + rng.uniform(-0.4, 0.4));
            addSegment(offsetPoint(path, s, off), offsetPoint(path, e, off), Material::Building, kClear);
            // Building returns come from deeper inside too (walls behind the facade, corners).
            if (rng.chance(0.3)) {
              const double back = off + side * rng.uniform(4.0, 15.0);
              addSegment(offsetPoint(path, s, back), offsetPoint(path, e, back), Material::Building, kClear);
            }
          }
          s = e;
        }
      } else {
        if (rng.chance(o.fence_probability)) {
          const double off = side * (half + 1.0);
          for (double s = s0; s < s0 + kBlock; s += 5.0)
            addSegment(offsetPoint(path, s, off), offsetPoint(path, s + 5.0, off), Material::Fence, kClear);
        } else if (rng.chance(o.hedge_probability)) {
          const double off = side * (half + 1.5);
          for (double s = s0; s < s0 + kBlock; s += 5.0)
            addSegment(offsetPoint(path, s, off), offsetPoint(path, s + 5.0, off), Material::Hedge, kClear);
        } else if (rng.chance(0.4)) {
          const double off = side * (half + 0.3);
          for (double s = s0; s < s0 + kBlock; s += 5.0)
            addSegment(offsetPoint(path, s, off), offsetPoint(path, s + 5.0, off), Material::Wall, kClear);
        }
        // Open land: scattered distant buildings, bushes and trees.
        // Open land: scattered distant buildings, bushes and trees, cars in car parks.
        const int n = rng.poisson(o.open_land_objects);
        for (int i = 0; i < n; ++i) {
          const double s = s0 + rng.uniform(0, kBlock), off = side * (half + rng.uniform(6.0, 60.0));
          const Eigen::Vector2d c = offsetPoint(path, s, off);
          const double a = mirroredAngle(s, rng.uniform(0, 2 * kPi)), kind = rng.uniform();
          if (kind < 0.35) {
            const double len = rng.uniform(4.0, 14.0);
            const Eigen::Vector2d d(std::cos(a) * len / 2, std::sin(a) * len / 2);
            addSegment(c - d, c + d, Material::Building, kClear);
          } else if (kind < 0.7) {
            addCircle(c, rng.uniform(1.0, 3.5), rng.chance(0.5) ? Material::Crown : Material::Hedge, kClear);
          } else {
            addBox(c, a, rng.uniform(3.9, 4.9), rng.uniform(1.7, 1.95), Material::Car);
          }
        }
      }
      // Parked cars along the kerb (on the oncoming side only where the road is wide).
      if (kerb > 0 || half > 6.2) {
        for (double s = s0; s < s0 + kBlock; s += 6.0) {
          if (!rng.chance(o.parked_car_probability)) continue;
          const Pose2 p = path.atArc(s + 3.0);
          const Eigen::Vector2d c = offsetPoint(path, s + 3.0, side * (half - 1.0));
          addBox(c, p.z() + mirror * rng.uniform(-0.05, 0.05), rng.uniform(3.9, 4.9), rng.uniform(1.7, 1.95),
                 Material::Car);
        }
      }
      // Poles (lamp posts, signs) and street trees.
      for (double s = s0 + rng.exponential(o.pole_spacing); s < s0 + kBlock; s += rng.exponential(o.pole_spacing))
        addCircle(offsetPoint(path, s, side * (half + 0.6)), 0.12, Material::Pole, kClear);
      for (double s = s0; s < s0 + kBlock; s += 12.0) {
        if (!rng.chance(o.tree_probability)) continue;
        const Eigen::Vector2d c = offsetPoint(path, s + rng.uniform(0, 12.0), side * (half + rng.uniform(1.8, 3.0)));
        addCircle(c, 0.2, Material::Trunk, kClear);
        if (clear(c, 0.0)) w.circles_.push_back({c, rng.uniform(1.2, 2.5), Material::Crown});
      }
    }
  }

  // Rows of buildings behind the street's facades, from their own stream (the street's draws stay).
  if (o.back_rows > 0) {
    Random back(o.seed, 0xbac4000000000000ULL);
    const int rows = static_cast<int>(std::lround(o.back_rows));
    for (int kerb : {+1, -1}) {
      const double side = mirror * kerb;
      for (int row = 1; row <= rows; ++row) {
        for (double s = -40.0; s < L + 40.0;) {
          const double len = back.uniform(5.0, 20.0);
          const double off = side * (o.road_half_width_max + 7.0 + row * o.back_row_spacing * back.uniform(0.7, 1.3));
          if (!back.chance(o.back_row_gap_probability))
            addSegment(offsetPoint(path, s, off), offsetPoint(path, s + len, off), Material::Building, kClear + 6.0);
          s += len;
        }
      }
    }
  }

  // Moving traffic: oncoming cars and buses in the opposite lane, and lead vehicles ahead of the ego.
  const double duration = path.endTime() - path.startTime();
  const int movers = static_cast<int>(std::lround(o.movers_per_km * L / 1000.0));
  for (int i = 0; i < movers; ++i) {
    Mover m;
    const bool bus = rng.chance(o.bus_share);
    m.material = bus ? Material::Bus : Material::Car;
    m.length = bus ? rng.uniform(10.0, 12.5) : rng.uniform(4.0, 4.9);
    m.width = bus ? 2.55 : rng.uniform(1.7, 1.95);
    m.follows_ego = rng.chance(0.25);
    if (m.follows_ego) {
      m.s0 = rng.uniform(12.0, 40.0);
      m.speed = 0.0;
      m.lateral = 0.0;
      m.t_start = path.startTime() + rng.uniform(0.0, duration);
      m.t_end = m.t_start + rng.uniform(10.0, 60.0);
    } else {
      m.speed = -rng.uniform(5.0, 13.0);
      m.lateral = -3.2 * mirror;
      m.t_start = path.startTime() + rng.uniform(-60.0, duration);
      m.t_end = m.t_start + 120.0;
      // Placed so that it meets the ego somewhere in its life.
      const double t_meet = std::min(std::max(m.t_start + rng.uniform(10.0, 60.0), path.startTime()), path.endTime());
      m.s0 = path.arcAt(t_meet) - m.speed * t_meet;
    }
    w.movers_.push_back(m);
  }
  w.index();
  return w;
}

World World::fromPrimitives(const SimTrajectory& path, std::vector<Segment> segments, std::vector<Circle> circles,
                            std::vector<Mover> movers) {
  World w;
  w.path_ = &path;
  w.clearance_ = std::make_shared<const PathClearance>(path);
  w.segments_ = std::move(segments);
  w.circles_ = std::move(circles);
  w.movers_ = std::move(movers);
  w.index();
  return w;
}

void World::index() {
  cell_items_.clear();
  auto insertBox = [&](Eigen::Vector2d lo, Eigen::Vector2d hi, std::uint32_t id) {
    const long x0 = static_cast<long>(std::floor(lo.x() / cell_)), x1 = static_cast<long>(std::floor(hi.x() / cell_));
    const long y0 = static_cast<long>(std::floor(lo.y() / cell_)), y1 = static_cast<long>(std::floor(hi.y() / cell_));
    for (long x = x0; x <= x1; ++x)
      for (long y = y0; y <= y1; ++y) cell_items_.emplace_back(cellKey(x, y), id);
  };
  for (std::size_t i = 0; i < segments_.size(); ++i)
    insertBox(segments_[i].a.cwiseMin(segments_[i].b), segments_[i].a.cwiseMax(segments_[i].b),
              static_cast<std::uint32_t>(i));
  for (std::size_t i = 0; i < circles_.size(); ++i) {
    const Eigen::Vector2d r(circles_[i].r, circles_[i].r);
    insertBox(circles_[i].c - r, circles_[i].c + r, static_cast<std::uint32_t>(segments_.size() + i));
  }
  std::sort(cell_items_.begin(), cell_items_.end());
  mailbox_.assign(segments_.size() + circles_.size(), 0);
  ray_id_ = 0;
}

double World::pathDistance(const Eigen::Vector2d& q) const {
  return clearance_ ? clearance_->distance(q) : 0.0;
}

void World::moverState(const Mover& m, double t, Pose2& pose, Eigen::Vector2d& velocity) const {
  auto at = [&](double tt) {
    const double s = m.follows_ego ? path_->arcAt(tt) + m.s0 : m.s0 + m.speed * tt;
    Pose2 p = path_->atArc(s);
    const Eigen::Vector2d c = offsetPoint(*path_, s, m.lateral);
    return Pose2(c.x(), c.y(), m.speed < 0 ? normalizeAngle(p.z() + kPi) : p.z());
  };
  pose = at(t);
  const Pose2 a = at(t - 0.05), b = at(t + 0.05);
  velocity = (b.head<2>() - a.head<2>()) / 0.1;
}

std::vector<int> World::activeMovers(const Eigen::Vector2d& centre, double radius, double t) const {
  std::vector<int> out;
  for (std::size_t i = 0; i < movers_.size(); ++i) {
    const Mover& m = movers_[i];
    if (t < m.t_start || t > m.t_end) continue;
    const double s = m.follows_ego ? path_->arcAt(t) + m.s0 : m.s0 + m.speed * t;
    if (s < 0.0 || s > path_->length()) continue;
    Pose2 p;
    Eigen::Vector2d v;
    moverState(m, t, p, v);
    if ((p.head<2>() - centre).norm() <= radius + m.length) out.push_back(static_cast<int>(i));
  }
  return out;
}

void World::cast(const Eigen::Vector2d& o, double angle, double t, double max_range, const std::vector<int>& movers,
                 std::vector<Hit>& hits) const {
  hits.clear();
  const Eigen::Vector2d d(std::cos(angle), std::sin(angle));
  double nearest_opaque = max_range;
  if (++ray_id_ == 0) {
    std::fill(mailbox_.begin(), mailbox_.end(), 0);
    ray_id_ = 1;
  }
  auto consider = [&](double range, double cos_inc, Material m, double depth, const Eigen::Vector2d& vel,
                      const Eigen::Vector2d& normal, std::uint32_t id) {
    if (range <= 1e-6 || range > nearest_opaque) return;
    hits.push_back({range, cos_inc, m, depth, vel, normal, id});
    if (materialModel(m).transmission <= 0.0) nearest_opaque = range;
  };
  auto testSegment = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b, Material m, const Eigen::Vector2d& vel,
                         std::uint32_t id) {
    const Eigen::Vector2d e = b - a;
    const double denom = cross(d, e);
    if (std::abs(denom) < 1e-12) return;
    const Eigen::Vector2d f = a - o;
    const double tt = cross(f, e) / denom, u = cross(f, d) / denom;
    if (tt <= 0.0 || u < 0.0 || u > 1.0) return;
    const double len = e.norm();
    Eigen::Vector2d n(-e.y() / len, e.x() / len);
    if (n.dot(d) > 0) n = -n;
    consider(tt, std::abs(denom) / len, m, materialModel(m).depth, vel, n, id);
  };
  auto testCircle = [&](const Circle& c, std::uint32_t id) {
    const Eigen::Vector2d f = o - c.c;
    const double b = f.dot(d), cc = f.squaredNorm() - c.r * c.r, disc = b * b - cc;
    if (disc <= 0.0 || cc <= 0.0) return;  // missed, or the origin is inside
    const double root = std::sqrt(disc), tt = -b - root;
    if (tt <= 0.0) return;
    const double depth = std::min(materialModel(c.material).depth, 2.0 * root);
    consider(tt, 1.0, c.material, depth, Eigen::Vector2d::Zero(), (o + tt * d - c.c) / c.r, id);
  };

  // Amanatides–Woo traversal of the grid cells along the ray.
  long ix = static_cast<long>(std::floor(o.x() / cell_)), iy = static_cast<long>(std::floor(o.y() / cell_));
  const int step_x = d.x() >= 0 ? 1 : -1, step_y = d.y() >= 0 ? 1 : -1;
  const double inv_x = std::abs(d.x()) > 1e-12 ? 1.0 / std::abs(d.x()) : 1e30;
  const double inv_y = std::abs(d.y()) > 1e-12 ? 1.0 / std::abs(d.y()) : 1e30;
  double next_x = ((step_x > 0 ? (ix + 1) * cell_ : ix * cell_) - o.x()) * step_x * inv_x;
  double next_y = ((step_y > 0 ? (iy + 1) * cell_ : iy * cell_) - o.y()) * step_y * inv_y;
  double entry = 0.0;
  const std::size_t nseg = segments_.size();
  while (entry <= nearest_opaque) {
    const std::int64_t key = cellKey(ix, iy);
    auto it = std::lower_bound(cell_items_.begin(), cell_items_.end(), std::make_pair(key, std::uint32_t{0}));
    for (; it != cell_items_.end() && it->first == key; ++it) {
      const std::uint32_t id = it->second;
      if (mailbox_[id] == ray_id_) continue;
      mailbox_[id] = ray_id_;
      if (id < nseg)
        testSegment(segments_[id].a, segments_[id].b, segments_[id].material, Eigen::Vector2d::Zero(), id);
      else
        testCircle(circles_[id - nseg], id);
    }
    if (next_x < next_y) {
      entry = next_x;
      next_x += cell_ * inv_x;
      ix += step_x;
    } else {
      entry = next_y;
      next_y += cell_ * inv_y;
      iy += step_y;
    }
  }
  for (int i : movers) {
    const Mover& m = movers_[i];
    Pose2 p;
    Eigen::Vector2d v;
    moverState(m, t, p, v);
    const Eigen::Vector2d c = p.head<2>(), u(std::cos(p.z()), std::sin(p.z())), n(-u.y(), u.x());
    const Eigen::Vector2d q[4] = {
        c + 0.5 * m.length * u + 0.5 * m.width * n, c - 0.5 * m.length * u + 0.5 * m.width * n,
        c - 0.5 * m.length * u - 0.5 * m.width * n, c + 0.5 * m.length * u - 0.5 * m.width * n};
    for (int k = 0; k < 4; ++k)
      testSegment(q[k], q[(k + 1) % 4], m.material, v, kMoverBit | static_cast<std::uint32_t>(i));
  }
  std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.range < b.range; });
  std::size_t keep = 0;
  while (keep < hits.size()) {
    if (materialModel(hits[keep++].material).transmission <= 0.0) break;
  }
  hits.resize(keep);
}

}  // namespace sim
}  // namespace radar_ndt

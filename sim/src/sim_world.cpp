// The simulator's world: the materials, the generated city along the trajectory, and ray casting.
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

/// Builds a world along a path from its options' random draws, in a fixed order: the street block
/// by block and side by side, the rows behind it from their own stream, then the traffic.
class WorldBuilder {
 public:
  WorldBuilder(const SimTrajectory& path, const WorldOptions& o, const PathClearance& clearance)
      : path_(path),
        o_(o),
        clearance_(clearance),
        rng_(o.seed, 0x5eed),
        mirror_(o.mirror != 0.0 ? -1.0 : 1.0),
        length_(path.length()) {}

  void buildStreet() {
    for (double s0 = -40.0; s0 < length_ + 40.0; s0 += kBlock)
      for (int kerb : {+1, -1}) buildBlockSide(s0, kerb);
  }
  void buildBackRows();
  void addTraffic();

  std::vector<Segment> segments;
  std::vector<Circle> circles;
  std::vector<Mover> movers;

 private:
  static constexpr double kBlock = 30.0;
  static constexpr double kClear = 2.2;  // m: nothing closer than this to any part of the path

  // Mirrored: every lateral offset and every orientation relative to the path is negated, with the
  // same random draws, so a seed gives the mirror image of its world (exact on a straight path).
  double mirroredAngle(double s, double a) const { return mirror_ > 0 ? a : 2.0 * path_.atArc(s).z() - a; }
  bool clear(const Eigen::Vector2d& p, double need) const { return clearance_.distance(p) >= need; }
  void addSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Material m, double need) {
    if ((b - a).norm() < 0.2) return;
    if (!clear(a, need) || !clear(b, need) || !clear(0.5 * (a + b), need)) return;
    segments.push_back({a, b, m});
  }
  void addBox(const Eigen::Vector2d& c, double heading, double length, double width, Material m) {
    // Mirrored, v flips too: the corners come in mirrored order, so each side keeps its index (and
    // with it its ghost draw).
    const Eigen::Vector2d u(std::cos(heading), std::sin(heading)), v = mirror_ * Eigen::Vector2d(-u.y(), u.x());
    const Eigen::Vector2d q[4] = {c + 0.5 * length * u + 0.5 * width * v, c - 0.5 * length * u + 0.5 * width * v,
                                  c - 0.5 * length * u - 0.5 * width * v, c + 0.5 * length * u - 0.5 * width * v};
    for (const auto& p : q)
      if (!clear(p, kClear)) return;
    for (int i = 0; i < 4; ++i) segments.push_back({q[i], q[(i + 1) % 4], m});
  }
  void addCircle(const Eigen::Vector2d& c, double r, Material m, double need) {
    if (!clear(c, need + r)) return;
    circles.push_back({c, r, m});
  }
  /// A row of 5 m pieces of `m` at lateral offset `off` along the block.
  void addRow(double s0, double off, Material m) {
    for (double s = s0; s < s0 + kBlock; s += 5.0)
      addSegment(offsetPoint(path_, s, off), offsetPoint(path_, s + 5.0, off), m, kClear);
  }
  void buildBlockSide(double s0, int kerb);
  void buildFacade(double s0, double side, double half);
  void buildOpenLand(double s0, double side, double half);
  void buildKerb(double s0, int kerb, double side, double half);

  const SimTrajectory& path_;
  const WorldOptions& o_;
  const PathClearance& clearance_;
  Random rng_;
  const double mirror_;
  const double length_;
};

void WorldBuilder::buildBlockSide(double s0, int kerb) {
  const double side = mirror_ * kerb;  // +1: left of the path
  const double half = rng_.uniform(o_.road_half_width_min, o_.road_half_width_max);
  if (rng_.chance(o_.building_probability))
    buildFacade(s0, side, half);
  else
    buildOpenLand(s0, side, half);
  buildKerb(s0, kerb, side, half);
}

void WorldBuilder::buildFacade(double s0, double side, double half) {
  // A facade: segments of 3–9 m with small set-backs, recesses and an occasional gap.
  const double setback = half + rng_.uniform(1.5, 7.0);
  double s = s0;
  while (s < s0 + kBlock) {
    const double len = rng_.uniform(3.0, 9.0);
    const double e = std::min(s + len, s0 + kBlock);
    if (!rng_.chance(o_.facade_gap_probability)) {
      const double off = side * (setback + rng_.uniform(-0.4, 0.4));
      addSegment(offsetPoint(path_, s, off), offsetPoint(path_, e, off), Material::Building, kClear);
      // Building returns come from deeper inside too (walls behind the facade, corners).
      if (rng_.chance(0.3)) {
        const double back = off + side * rng_.uniform(4.0, 15.0);
        addSegment(offsetPoint(path_, s, back), offsetPoint(path_, e, back), Material::Building, kClear);
      }
    }
    s = e;
  }
}

void WorldBuilder::buildOpenLand(double s0, double side, double half) {
  if (rng_.chance(o_.fence_probability))
    addRow(s0, side * (half + 1.0), Material::Fence);
  else if (rng_.chance(o_.hedge_probability))
    addRow(s0, side * (half + 1.5), Material::Hedge);
  else if (rng_.chance(0.4))
    addRow(s0, side * (half + 0.3), Material::Wall);
  // Open land: scattered distant buildings, bushes and trees, cars in car parks.
  const int n = rng_.poisson(o_.open_land_objects);
  for (int i = 0; i < n; ++i) {
    const double s = s0 + rng_.uniform(0, kBlock), off = side * (half + rng_.uniform(6.0, 60.0));
    const Eigen::Vector2d c = offsetPoint(path_, s, off);
    const double a = mirroredAngle(s, rng_.uniform(0, 2 * kPi)), kind = rng_.uniform();
    if (kind < 0.35) {
      const double len = rng_.uniform(4.0, 14.0);
      const Eigen::Vector2d d(std::cos(a) * len / 2, std::sin(a) * len / 2);
      addSegment(c - d, c + d, Material::Building, kClear);
    } else if (kind < 0.7) {
      addCircle(c, rng_.uniform(1.0, 3.5), rng_.chance(0.5) ? Material::Crown : Material::Hedge, kClear);
    } else {
      addBox(c, a, rng_.uniform(3.9, 4.9), rng_.uniform(1.7, 1.95), Material::Car);
    }
  }
}

void WorldBuilder::buildKerb(double s0, int kerb, double side, double half) {
  // Parked cars along the kerb (on the oncoming side only where the road is wide).
  if (kerb > 0 || half > 6.2) {
    for (double s = s0; s < s0 + kBlock; s += 6.0) {
      if (!rng_.chance(o_.parked_car_probability)) continue;
      const Pose2 p = path_.atArc(s + 3.0);
      const Eigen::Vector2d c = offsetPoint(path_, s + 3.0, side * (half - 1.0));
      addBox(c, p.z() + mirror_ * rng_.uniform(-0.05, 0.05), rng_.uniform(3.9, 4.9), rng_.uniform(1.7, 1.95),
             Material::Car);
    }
  }
  // Poles (lamp posts, signs) and street trees.
  for (double s = s0 + rng_.exponential(o_.pole_spacing); s < s0 + kBlock; s += rng_.exponential(o_.pole_spacing))
    addCircle(offsetPoint(path_, s, side * (half + 0.6)), 0.12, Material::Pole, kClear);
  for (double s = s0; s < s0 + kBlock; s += 12.0) {
    if (!rng_.chance(o_.tree_probability)) continue;
    const Eigen::Vector2d c = offsetPoint(path_, s + rng_.uniform(0, 12.0), side * (half + rng_.uniform(1.8, 3.0)));
    addCircle(c, 0.2, Material::Trunk, kClear);
    if (clear(c, 0.0)) circles.push_back({c, rng_.uniform(1.2, 2.5), Material::Crown});
  }
}

void WorldBuilder::buildBackRows() {
  // Rows of buildings behind the street's facades, from their own stream (the street's draws stay).
  if (!(o_.back_rows > 0)) return;
  Random back(o_.seed, 0xbac4000000000000ULL);
  const int rows = static_cast<int>(std::lround(o_.back_rows));
  for (int kerb : {+1, -1}) {
    const double side = mirror_ * kerb;
    for (int row = 1; row <= rows; ++row) {
      for (double s = -40.0; s < length_ + 40.0;) {
        const double len = back.uniform(5.0, 20.0);
        const double off = side * (o_.road_half_width_max + 7.0 + row * o_.back_row_spacing * back.uniform(0.7, 1.3));
        if (!back.chance(o_.back_row_gap_probability))
          addSegment(offsetPoint(path_, s, off), offsetPoint(path_, s + len, off), Material::Building, kClear + 6.0);
        s += len;
      }
    }
  }
}

void WorldBuilder::addTraffic() {
  // Moving traffic: oncoming cars and buses in the opposite lane, and lead vehicles ahead of the ego.
  const double duration = path_.endTime() - path_.startTime();
  const int count = static_cast<int>(std::lround(o_.movers_per_km * length_ / 1000.0));
  for (int i = 0; i < count; ++i) {
    Mover m;
    const bool bus = rng_.chance(o_.bus_share);
    m.material = bus ? Material::Bus : Material::Car;
    m.length = bus ? rng_.uniform(10.0, 12.5) : rng_.uniform(4.0, 4.9);
    m.width = bus ? 2.55 : rng_.uniform(1.7, 1.95);
    m.follows_ego = rng_.chance(0.25);
    if (m.follows_ego) {
      m.s0 = rng_.uniform(12.0, 40.0);
      m.speed = 0.0;
      m.lateral = 0.0;
      m.t_start = path_.startTime() + rng_.uniform(0.0, duration);
      m.t_end = m.t_start + rng_.uniform(10.0, 60.0);
    } else {
      m.speed = -rng_.uniform(5.0, 13.0);
      m.lateral = -3.2 * mirror_;
      m.t_start = path_.startTime() + rng_.uniform(-60.0, duration);
      m.t_end = m.t_start + 120.0;
      // Placed so that it meets the ego somewhere in its life.
      const double t_meet =
          std::min(std::max(m.t_start + rng_.uniform(10.0, 60.0), path_.startTime()), path_.endTime());
      m.s0 = path_.arcAt(t_meet) - m.speed * t_meet;
    }
    movers.push_back(m);
  }
}

}  // namespace

World World::generate(const SimTrajectory& path, const WorldOptions& o) {
  o.validate();
  World w;
  w.path_ = &path;
  w.clearance_ = std::make_shared<const PathClearance>(path);
  WorldBuilder builder(path, o, *w.clearance_);
  builder.buildStreet();
  builder.buildBackRows();
  builder.addTraffic();
  w.segments_ = std::move(builder.segments);
  w.circles_ = std::move(builder.circles);
  w.movers_ = std::move(builder.movers);
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

namespace {

/// One ray's hits: each primitive tested against the ray, kept when nearer than the first opaque
/// surface found so far.
struct RayHits {
  const Eigen::Vector2d& o;
  const Eigen::Vector2d d;
  double nearest_opaque;
  std::vector<Hit>& hits;

  void consider(double range, double cos_inc, Material m, double depth, const Eigen::Vector2d& vel,
                const Eigen::Vector2d& normal, std::uint32_t id) {
    if (range <= 1e-6 || range > nearest_opaque) return;
    hits.push_back({range, cos_inc, m, depth, vel, normal, id});
    if (materialModel(m).transmission <= 0.0) nearest_opaque = range;
  }
  void testSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Material m, const Eigen::Vector2d& vel,
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
  }
  void testCircle(const Circle& c, std::uint32_t id) {
    const Eigen::Vector2d f = o - c.c;
    const double b = f.dot(d), cc = f.squaredNorm() - c.r * c.r, disc = b * b - cc;
    if (disc <= 0.0 || cc <= 0.0) return;  // missed, or the origin is inside
    const double root = std::sqrt(disc), tt = -b - root;
    if (tt <= 0.0) return;
    const double depth = std::min(materialModel(c.material).depth, 2.0 * root);
    consider(tt, 1.0, c.material, depth, Eigen::Vector2d::Zero(), (o + tt * d - c.c) / c.r, id);
  }
  /// Nearest first, ending at the first opaque one.
  void finish() {
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.range < b.range; });
    std::size_t keep = 0;
    while (keep < hits.size()) {
      if (materialModel(hits[keep++].material).transmission <= 0.0) break;
    }
    hits.resize(keep);
  }
};

}  // namespace

void World::cast(const Eigen::Vector2d& o, double angle, double t, double max_range, const std::vector<int>& movers,
                 std::vector<Hit>& hits) const {
  hits.clear();
  if (++ray_id_ == 0) {
    std::fill(mailbox_.begin(), mailbox_.end(), 0);
    ray_id_ = 1;
  }
  RayHits ray{o, Eigen::Vector2d(std::cos(angle), std::sin(angle)), max_range, hits};
  castStatic(ray);
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
      ray.testSegment(q[k], q[(k + 1) % 4], m.material, v, kMoverBit | static_cast<std::uint32_t>(i));
  }
  ray.finish();
}

template <typename Ray>
void World::castStatic(Ray& ray) const {
  // Amanatides–Woo traversal of the grid cells along the ray, each primitive tested once (mailbox).
  const Eigen::Vector2d& o = ray.o;
  const Eigen::Vector2d& d = ray.d;
  long ix = static_cast<long>(std::floor(o.x() / cell_)), iy = static_cast<long>(std::floor(o.y() / cell_));
  const int step_x = d.x() >= 0 ? 1 : -1, step_y = d.y() >= 0 ? 1 : -1;
  const double inv_x = std::abs(d.x()) > 1e-12 ? 1.0 / std::abs(d.x()) : 1e30;
  const double inv_y = std::abs(d.y()) > 1e-12 ? 1.0 / std::abs(d.y()) : 1e30;
  double next_x = ((step_x > 0 ? (ix + 1) * cell_ : ix * cell_) - o.x()) * step_x * inv_x;
  double next_y = ((step_y > 0 ? (iy + 1) * cell_ : iy * cell_) - o.y()) * step_y * inv_y;
  double entry = 0.0;
  const std::size_t nseg = segments_.size();
  while (entry <= ray.nearest_opaque) {
    const std::int64_t key = cellKey(ix, iy);
    auto it = std::lower_bound(cell_items_.begin(), cell_items_.end(), std::make_pair(key, std::uint32_t{0}));
    for (; it != cell_items_.end() && it->first == key; ++it) {
      const std::uint32_t id = it->second;
      if (mailbox_[id] == ray_id_) continue;
      mailbox_[id] = ray_id_;
      if (id < nseg)
        ray.testSegment(segments_[id].a, segments_[id].b, segments_[id].material, Eigen::Vector2d::Zero(), id);
      else
        ray.testCircle(circles_[id - nseg], id);
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
}

}  // namespace sim
}  // namespace radar_ndt

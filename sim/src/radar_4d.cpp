#include "radar_ndt/sim/radar_4d.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "sim_random.h"

namespace radar_ndt {
namespace sim {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

/// Slab test: the entry distance of the ray into an axis-aligned box, if within (0, best).
bool hitBox(const Box3& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double& best) {
  double t0 = 0.0, t1 = best;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d(k)) < 1e-12) {
      if (o(k) < b.min(k) || o(k) > b.max(k)) return false;
      continue;
    }
    double a = (b.min(k) - o(k)) / d(k), c = (b.max(k) - o(k)) / d(k);
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
    if (t0 > t1) return false;
  }
  if (!(t0 > 1e-6) || t0 >= best) return false;  // a ray starting inside a box sees nothing of it
  best = t0;
  return true;
}

bool hitPole(const Pole3& p, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double& best) {
  const double ox = o.x() - p.xy.x(), oy = o.y() - p.xy.y();
  const double a = d.x() * d.x() + d.y() * d.y();
  if (a < 1e-12) return false;
  const double b = 2 * (ox * d.x() + oy * d.y()), c = ox * ox + oy * oy - p.radius * p.radius;
  const double disc = b * b - 4 * a * c;
  if (disc < 0) return false;
  const double t = (-b - std::sqrt(disc)) / (2 * a);
  if (!(t > 1e-6) || t >= best) return false;
  const double z = o.z() + t * d.z();
  if (z < 0 || z > p.height) return false;
  best = t;
  return true;
}

bool hitPatch(const Patch3& p, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double& best) {
  const Eigen::Vector3d n = p.u.cross(p.v);
  const double den = n.dot(d);
  if (std::abs(den) < 1e-12) return false;
  const double t = n.dot(p.origin - o) / den;
  if (!(t > 1e-6) || t >= best) return false;
  // Solve origin + s u + w v = hit for (s, w) in the patch's plane.
  const Eigen::Vector3d h = o + t * d - p.origin;
  const double uu = p.u.dot(p.u), uv = p.u.dot(p.v), vv = p.v.dot(p.v);
  const double hu = h.dot(p.u), hv = h.dot(p.v), det = uu * vv - uv * uv;
  const double s = (hu * vv - hv * uv) / det, w = (hv * uu - hu * uv) / det;
  if (s < 0 || s > 1 || w < 0 || w > 1) return false;
  best = t;
  return true;
}

}  // namespace

bool World3D::cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double max_range, double* range,
                   float* rcs) const {
  double best = max_range;
  float hit_rcs = 0;
  bool hit = false;
  for (const Box3& b : boxes)
    if (hitBox(b, o, d, best)) hit = true, hit_rcs = b.rcs;
  for (const Pole3& p : poles)
    if (hitPole(p, o, d, best)) hit = true, hit_rcs = p.rcs;
  for (const Patch3& p : patches)
    if (hitPatch(p, o, d, best)) hit = true, hit_rcs = p.rcs;
  if (hit) {
    *range = best;
    *rcs = hit_rcs;
  }
  return hit;
}

World3D streetWorld(double length, std::uint64_t seed) {
  Random rng(seed, 0x5747);
  World3D w;
  const double x0 = -50, x1 = length + 50;
  // The ground, and a ramp up to a raised stretch (3 m over 30 m) half-way.
  const double ramp_x = 0.5 * length, ramp_len = 30, rise = 3;
  w.patches.push_back({{x0, -30, 0}, {ramp_x - x0, 0, 0}, {0, 60, 0}});
  w.patches.push_back({{ramp_x, -30, 0}, {ramp_len, 0, rise}, {0, 60, 0}});
  w.patches.push_back({{ramp_x + ramp_len, -30, rise}, {x1 - ramp_x - ramp_len, 0, 0}, {0, 60, 0}});
  auto ground = [&](double x) {
    return x < ramp_x ? 0.0 : x < ramp_x + ramp_len ? rise * (x - ramp_x) / ramp_len : rise;
  };
  for (int side : {-1, 1}) {
    for (double x = x0; x < x1;) {
      const double len = rng.uniform(8, 25), gap = rng.chance(0.3) ? rng.uniform(4, 12) : 0.5;
      const double setback = rng.uniform(9, 14), depth = rng.uniform(6, 15), height = rng.uniform(6, 20);
      const double y_in = side * setback, y_out = side * (setback + depth);
      const double gz = std::min(ground(x), ground(x + len));
      w.boxes.push_back({{x, std::min(y_in, y_out), gz - 1}, {x + len, std::max(y_in, y_out), gz + height}, 15.f});
      x += len + gap;
    }
    for (double x = x0 + rng.uniform(0, 10); x < x1; x += rng.uniform(12, 30)) {
      const double gz = ground(x);
      w.poles.push_back({{x, side * rng.uniform(6.5, 8.0)}, rng.uniform(0.1, 0.25), gz + rng.uniform(3, 8), 5.f});
    }
    for (double x = x0 + rng.uniform(0, 15); x < x1; x += rng.uniform(6, 25)) {  // parked cars
      if (!rng.chance(0.6)) continue;
      const double gz = ground(x), y = side * rng.uniform(4.2, 5.2);
      w.boxes.push_back({{x, y - 0.9, gz}, {x + 4.5, y + 0.9, gz + 1.5}, 10.f});
    }
  }
  return w;
}

World3D corridorWorld(std::uint64_t seed) {
  Random rng(seed, 0xc0dd);
  World3D w;
  const double floor_h = 3.0;
  w.patches.push_back({{-35, -25, 0}, {70, 0, 0}, {0, 50, 0}, -5.f});        // floor
  w.patches.push_back({{-35, -25, floor_h}, {70, 0, 0}, {0, 50, 0}, -5.f});  // ceiling
  const double t = 0.25;                                                     // wall thickness
  auto wall = [&](double xa, double ya, double xb, double yb) {              // axis-aligned, with doors
    const bool along_x = std::abs(yb - ya) < 1e-9;
    const double a0 = along_x ? std::min(xa, xb) : std::min(ya, yb), a1 = along_x ? std::max(xa, xb) : std::max(ya, yb);
    for (double a = a0; a < a1;) {
      const double seg = std::min(a1 - a, rng.uniform(3, 9));
      const Eigen::Vector3d lo = along_x ? Eigen::Vector3d(a, ya - t, 0) : Eigen::Vector3d(xa - t, a, 0);
      const Eigen::Vector3d hi =
          along_x ? Eigen::Vector3d(a + seg, ya + t, floor_h) : Eigen::Vector3d(xa + t, a + seg, floor_h);
      w.boxes.push_back({lo, hi, 12.f});
      a += seg + (rng.chance(0.5) ? 1.0 : 0.0);  // a door
    }
  };
  // A loop of corridors 2.4 m wide around a block of rooms, and a cross corridor.
  wall(-30, -20, 30, -20);
  wall(-30, -17.6, 30, -17.6);
  wall(-30, 20, 30, 20);
  wall(-30, 17.6, 30, 17.6);
  wall(-30, -20, -30, 20);
  wall(-27.6, -17.6, -27.6, 17.6);
  wall(30, -20, 30, 20);
  wall(27.6, -17.6, 27.6, 17.6);
  wall(-27.6, -1.2, 27.6, -1.2);
  wall(-27.6, 1.2, 27.6, 1.2);
  for (int i = 0; i < 24; ++i) {  // pillars, cabinets
    const double x = rng.uniform(-29, 29), y = rng.chance(0.5) ? rng.uniform(-19.5, -18) : rng.uniform(18, 19.5);
    const double s = rng.uniform(0.3, 0.8), h = rng.uniform(1.0, floor_h);
    w.boxes.push_back({{x, y - 0.5 * s, 0}, {x + s, y + 0.5 * s, h}, 8.f});
  }
  for (int k = 0; k < 12; ++k) {  // a staircase at the east end: steps of 0.25 m
    const double x = 22 + 0.3 * k;
    w.boxes.push_back({{x, -1.1, 0}, {x + 0.3, 0.0, 0.25 * (k + 1)}, 6.f});
  }
  return w;
}

Radar4DModel radar4DPreset(const std::string& name) {
  Radar4DModel m;
  m.name = name;
  if (name == "ti_iwr6843_rio") {
    // TI IWR6843AOP as the rio rig runs it: a wide antenna-on-package field of view, an office's
    // ranges, a few dozen detections a scan.
    m.azimuth_fov_deg = 130;
    m.elevation_fov_deg = 70;
    m.min_range = 0.5;
    m.max_range = 20;
    m.accuracy = {0.05, 3.0, 6.0};
    m.doppler_sigma = 0.03;
    m.rays = 110;
    m.detection_probability = 0.7;
    m.false_alarms = 2;
    m.ghost_fraction = 0.05;
    m.snr_offset = 17;
    m.snr_sigma = 5;
    m.min_snr = 6;
  } else if (name == "ars548") {
    // Continental ARS548 RDI: long range, ±60° azimuth, a narrow elevation, up to 800 detections.
    m.azimuth_fov_deg = 120;
    m.elevation_fov_deg = 28;
    m.min_range = 0.5;
    m.max_range = 300;
    m.accuracy = {0.15, 0.3, 0.3};
    m.doppler_sigma = 0.1;
    m.rays = 900;
    m.detection_probability = 0.6;
    m.false_alarms = 20;
    m.ghost_fraction = 0.02;
  } else if (name == "oculii_eagle") {
    // Oculii (Ambarella) EAGLE: 120° x 30°, fine angles, thousands of points a frame.
    m.azimuth_fov_deg = 120;
    m.elevation_fov_deg = 30;
    m.min_range = 0.5;
    m.max_range = 200;
    m.accuracy = {0.1, 0.5, 1.0};
    m.doppler_sigma = 0.05;
    m.rays = 3000;
    m.detection_probability = 0.7;
    m.false_alarms = 40;
    m.ghost_fraction = 0.02;
  } else {
    throw std::invalid_argument("radar4DPreset: unknown preset '" + name + "' (ti_iwr6843_rio, ars548, oculii_eagle)");
  }
  return m;
}

std::vector<std::string> radar4DPresetNames() {
  return {"ti_iwr6843_rio", "ars548", "oculii_eagle"};
}

std::string radar4DSensorPreset(const std::string& preset) {
  if (preset == "ti_iwr6843_rio") return "ti_iwr6843_rio";
  if (preset == "ars548") return "snail_radar_ars548";
  if (preset == "oculii_eagle") return "ntu4dradlm_eagle";
  throw std::invalid_argument("radar4DSensorPreset: unknown preset '" + preset +
                              "' (ti_iwr6843_rio, ars548, oculii_eagle)");
}

pcl::PointCloud<PointRadar4D> simulateScan4D(const World3D& world, const Pose3& pose, const Eigen::Vector3d& velocity,
                                             const Radar4DModel& m, std::uint64_t seed, std::uint64_t stream) {
  Random rng(seed, stream);
  pcl::PointCloud<PointRadar4D> out;
  const Eigen::Matrix3d R = pose.linear();
  const Eigen::Vector3d o = pose.translation();
  const Eigen::Vector3d v_sensor = R.transpose() * velocity;
  auto add = [&](double r, double az, double el, float rcs, double radial) {
    const double rn = r + m.accuracy.range_sigma * rng.normal();
    const double an = az + m.accuracy.azimuth_sigma_deg * kDeg * rng.normal();
    const double en = el + m.accuracy.elevation_sigma_deg * kDeg * rng.normal();
    if (!(rn > m.min_range)) return;
    PointRadar4D p(static_cast<float>(rn * std::cos(en) * std::cos(an)),
                   static_cast<float>(rn * std::cos(en) * std::sin(an)), static_cast<float>(rn * std::sin(en)));
    // Power as an SNR in dB (the TI driver's intensity): RCS less the two-way spreading loss; below
    // the driver's threshold the detection is not reported.
    const double snr = m.snr_offset + rcs - 20.0 * std::log10(std::max(rn, 1.0)) + m.snr_sigma * rng.normal();
    if (m.min_snr > 0 && snr < m.min_snr) return;
    p.power = static_cast<float>(std::max(1.0, snr));
    p.rcs = rcs;
    p.doppler = static_cast<float>(radial + m.doppler_sigma * rng.normal());
    out.push_back(p);
  };
  for (int i = 0; i < m.rays; ++i) {
    const double az = rng.uniform(-0.5, 0.5) * m.azimuth_fov_deg * kDeg;
    const double el = rng.uniform(-0.5, 0.5) * m.elevation_fov_deg * kDeg;
    const Eigen::Vector3d ds(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    double r = 0;
    float rcs = 0;
    if (!world.cast(o, R * ds, m.max_range, &r, &rcs) || r < m.min_range) continue;
    if (!rng.chance(m.detection_probability)) continue;
    const double radial = -v_sensor.dot(ds);  // a static target recedes as the sensor moves away
    if (rng.chance(m.ghost_fraction)) {
      // Multipath off the ground: the target seen mirrored below it, at a longer path.
      const Eigen::Vector3d hit = R * ds * r + o;
      const Eigen::Vector3d ghost_w(hit.x(), hit.y(), -hit.z() - 0.5);
      const Eigen::Vector3d g = R.transpose() * (ghost_w - o);
      const double gr = g.norm();
      if (gr < m.max_range) add(gr, std::atan2(g.y(), g.x()), std::asin(g.z() / gr), rcs - 6.f, radial);
      continue;
    }
    add(r, az, el, rcs, radial);
  }
  const int alarms = static_cast<int>(std::floor(m.false_alarms * 2 * rng.uniform()));  // mean false_alarms
  for (int i = 0; i < alarms; ++i)
    add(rng.uniform(m.min_range, m.max_range), rng.uniform(-0.5, 0.5) * m.azimuth_fov_deg * kDeg,
        rng.uniform(-0.5, 0.5) * m.elevation_fov_deg * kDeg, -10.f, rng.uniform(-5, 5));
  setPointCovariances(out, Eigen::Matrix3d::Identity(), m.accuracy);
  return out;
}

namespace {

/// The sensor's pose at time t: a car along the street (a gentle S-curve, on the ramp's height),
/// or a walk at 1.4 m/s round the corridor loop with a hand-held rig's wobble.
Pose3 pathPose(const ScanToMapOptions& o, double t) {
  Pose3 T = Pose3::Identity();
  if (o.preset == "ti_iwr6843_rio") {
    const double s = 1.4 * t;  // along the south corridor, eastwards, 1.3 m above the floor
    const double yaw = 0.15 * std::sin(0.4 * s), roll = 0.05 * std::sin(5.5 * t), pitch = 0.06 * std::sin(3.7 * t + 1);
    T.linear() =
        (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    T.translation() = Eigen::Vector3d(-25 + s, -18.8 + 0.3 * std::sin(0.3 * s), 1.3 + 0.03 * std::sin(11 * t));
    return T;
  }
  const double s = o.speed * t, y = 1.5 * std::sin(s / 40.0);
  const double yaw = std::atan(1.5 / 40.0 * std::cos(s / 40.0));
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(s, y, 0.8);
  return T;
}

}  // namespace

ScanToMapPair scanToMapPair(const ScanToMapOptions& o, std::uint64_t seed, int index) {
  Radar4DModel model = radar4DPreset(o.preset);
  model.accuracy.range_sigma *= o.noise_scale;
  model.accuracy.azimuth_sigma_deg *= o.noise_scale;
  model.accuracy.elevation_sigma_deg *= o.noise_scale;
  model.doppler_sigma *= o.noise_scale;
  const bool handheld = o.preset == "ti_iwr6843_rio";
  const double period = handheld ? 0.1 : o.scan_period;
  const World3D world = handheld ? corridorWorld(seed) : streetWorld(400, seed);
  const double t0 = (handheld ? 1.0 : 2.0) + index * 0.7 * period * (o.map_scans + 1);
  ScanToMapPair pair;
  // The map in the frame of its first scan's pose, so the truth is a motion of a few metres.
  const Pose3 origin = pathPose(o, t0);
  for (int k = 0; k < o.map_scans; ++k) {
    const double t = t0 + k * period;
    const Pose3 pose = pathPose(o, t);
    const Eigen::Vector3d vel = (pathPose(o, t + 1e-3).translation() - pose.translation()) / 1e-3;
    pcl::PointCloud<PointRadar4D> scan = simulateScan4D(world, pose, vel, model, seed, 1000 * index + k);
    const Pose3 in_map = origin.inverse() * pose;
    setPointCovariances(scan, in_map.linear(), model.accuracy);  // in the map's frame, from the sensor's points
    for (auto& p : scan) {
      const Eigen::Vector3d q = in_map * Eigen::Vector3d(p.x, p.y, p.z);
      p.x = static_cast<float>(q.x());
      p.y = static_cast<float>(q.y());
      p.z = static_cast<float>(q.z());
    }
    pair.map += scan;
  }
  const double ts = t0 + o.map_scans * period;
  const Pose3 pose = pathPose(o, ts);
  const Eigen::Vector3d vel = (pathPose(o, ts + 1e-3).translation() - pose.translation()) / 1e-3;
  pair.source = simulateScan4D(world, pose, vel, model, seed, 1000 * index + 999);
  pair.truth = origin.inverse() * pose;
  Random rng(seed, 77777 + static_cast<std::uint64_t>(index));
  Eigen::Vector3d dt(rng.normal(), rng.normal(), rng.normal()), dr(rng.normal(), rng.normal(), rng.normal());
  dt = dt.normalized() * o.translation_error;
  dr = dr.normalized() * o.rotation_error;
  pair.guess = pair.truth;
  pair.guess.translation() += dt;
  pair.guess.linear() = expSO3(dr) * pair.truth.linear();
  return pair;
}

}  // namespace sim
}  // namespace radar_ndt

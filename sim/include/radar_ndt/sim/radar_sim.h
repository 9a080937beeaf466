#pragma once
// radar_sim: a scanning-radar (Navtech CTS350-X) and automotive-radar (Continental ARS408)
// simulator in a procedurally generated 2D world, driven along a given trajectory. It is the only
// source of scanning-radar data with ground truth here, so it models what makes real scans hard:
// per-azimuth acquisition times (motion distortion), beam-width and range smearing, power falling
// with range and depending on the material, occlusion, speckle, multipath ghosts, receiver
// saturation lines, near-range leakage and a range-dependent noise floor; moving cars and buses.
// Everything is deterministic for a seed: each frame draws from its own generator seeded by
// (seed, frame), so a frame does not depend on which frames were rendered before it.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/sim/imu_model.h"
#include "radar_ndt/sim/sim_options.h"

namespace radar_ndt {
namespace sim {

/// A planar trajectory with timestamps, interpolated in time (position linearly, heading along
/// the shortest arc) and by arc length.
class SimTrajectory {
 public:
  SimTrajectory() = default;
  /// Poses of `trajectory` (projected to SE(2)); its stamps when it has them, else k · period.
  SimTrajectory(const Trajectory& trajectory, double period);
  SimTrajectory(std::vector<double> stamps, std::vector<Pose2> poses);

  std::size_t size() const { return poses_.size(); }
  double startTime() const { return stamps_.front(); }
  double endTime() const { return stamps_.back(); }
  const std::vector<double>& stamps() const { return stamps_; }
  const std::vector<Pose2>& poses() const { return poses_; }
  /// Pose at time t (clamped to the ends).
  Pose2 at(double t) const;
  /// Body-frame velocity (vx, vy, ω) at time t, from the segment around t.
  Eigen::Vector3d velocity(double t) const;
  double length() const { return arc_.empty() ? 0.0 : arc_.back(); }
  /// Position and heading at arc length s along the path; beyond the ends, straight on.
  Pose2 atArc(double s) const;
  /// Arc length travelled at time t.
  double arcAt(double t) const;

 private:
  std::size_t segment(double t) const;
  std::vector<double> stamps_;
  std::vector<Pose2> poses_;
  std::vector<double> arc_;                         ///< cumulative path length at each pose
  double start_heading_ = 0.0, end_heading_ = 0.0;  ///< direction of travel at the ends (for atArc beyond them)
};

/// A built-in city drive for demos and tests (no file needed): pulls away, cruises at up to
/// 12 m/s with left and right 90° turns, a bend and a stop at a junction; poses every `period` s.
SimTrajectory builtinDrive(double duration, double period = 0.25);

enum class Material : std::uint8_t { Building, Car, Bus, Pole, Trunk, Crown, Fence, Hedge, Wall };
const char* toString(Material m);

/// What each material returns and lets through. Power in dB relative to a building facade hit
/// at normal incidence at 10 m.
struct MaterialModel {
  double reflect_db;     ///< power at 10 m, normal incidence
  double transmission;   ///< share of the power that goes on behind it (0: opaque)
  double depth;          ///< m of range over which it returns (volume scattering)
  double incidence_exp;  ///< power ∝ |cos incidence|^exp (0: cylinders, rough surfaces)
  double rcs_dbsm;       ///< ARS408 radar cross-section of one detection
};
const MaterialModel& materialModel(Material m);

struct Segment {
  Eigen::Vector2d a, b;
  Material material;
};
struct Circle {
  Eigen::Vector2d c;
  double r;
  Material material;
};
/// A vehicle moving along the ego path at its own constant speed, in its own lane.
struct Mover {
  double s0;         ///< arc length at t = 0 (or, following the ego, the gap ahead of it)
  double speed;      ///< m/s along the path (negative: oncoming)
  bool follows_ego;  ///< drives the ego's own path `s0` metres ahead of it, at its speed
  double lateral;    ///< m left of the path's centre line
  double length, width;
  double t_start, t_end;  ///< alive between these times (s)
  Material material;
};

struct Hit {
  double range;  ///< m from the ray origin
  double cos_incidence;
  Material material;
  double depth;              ///< m of range the return spreads over
  Eigen::Vector2d velocity;  ///< world-frame velocity of the surface (movers), m/s
  Eigen::Vector2d normal;    ///< unit surface normal facing the ray origin
  std::uint32_t id;          ///< primitive id (segments, then circles); movers: kMoverBit | index
};
constexpr std::uint32_t kMoverBit = 0x80000000u;

class PathClearance;

/// The generated world: static segments and circles along the path, with a grid index, and the
/// movers. Rays see everything up to and including the first opaque surface. cast() keeps
/// per-world scratch state: one world is used by one thread at a time.
class World {
 public:
  static World generate(const SimTrajectory& path, const WorldOptions& options);
  /// A world of given primitives (tests, hand-made scenes). Movers follow `path`. The world keeps
  /// a pointer to `path`, as generate() does: it must outlive the world.
  static World fromPrimitives(const SimTrajectory& path, std::vector<Segment> segments, std::vector<Circle> circles,
                              std::vector<Mover> movers = {});

  /// Hits along the ray from `origin` in direction `angle` (world frame) at time t, nearest
  /// first, up to `max_range`, ending at the first opaque one. `movers` restricts the movers
  /// tested (indices from activeMovers()).
  void cast(const Eigen::Vector2d& origin, double angle, double t, double max_range, const std::vector<int>& movers,
            std::vector<Hit>& hits) const;
  /// Distance (m) from `q` to the nearest point of the path, up to 12 m (farther: 12).
  double pathDistance(const Eigen::Vector2d& q) const;
  /// Movers alive at t within `radius` of `centre`.
  std::vector<int> activeMovers(const Eigen::Vector2d& centre, double radius, double t) const;
  /// A mover's pose (x, y, heading) and world velocity at time t.
  void moverState(const Mover& m, double t, Pose2& pose, Eigen::Vector2d& velocity) const;

  const std::vector<Segment>& segments() const { return segments_; }
  const std::vector<Circle>& circles() const { return circles_; }
  const std::vector<Mover>& movers() const { return movers_; }

 private:
  void index();
  /// The static primitives along a cast's ray (the grid traversal); `Ray` tests and keeps hits.
  template <typename Ray>
  void castStatic(Ray& ray) const;
  const SimTrajectory* path_ = nullptr;
  std::shared_ptr<const PathClearance> clearance_;
  std::vector<Segment> segments_;
  std::vector<Circle> circles_;
  std::vector<Mover> movers_;
  double cell_ = 8.0;
  // grid cell key → primitive ids (segments: id, circles: id + segments_.size())
  std::vector<std::pair<std::int64_t, std::uint32_t>> cell_items_;  // sorted by key
  mutable std::vector<std::uint32_t> mailbox_;
  mutable std::uint32_t ray_id_ = 0;
};

struct SequenceOptions {
  std::size_t start = 0;   ///< first trajectory pose used
  std::size_t frames = 0;  ///< frames written (scans / front-radar sweeps); 0: as many as the trajectory has
  std::int64_t start_stamp_us = 1547120000000000;  ///< the first frame's timestamp
  int png_compression = 1;                         ///< zlib level of the scan PNGs (fast)
  bool progress = false;                           ///< a progress line on stderr
  std::string scene_name = "sim-0001";             ///< automotive: the scene's name in scene.json
  /// Throws std::invalid_argument naming the first setting out of range.
  void validate() const;
};

/// One scan at time `t` (s, trajectory time) rendered into `scan` (Oxford conventions).
/// `frame` seeds the scan's random draws together with the world's seed.
void renderScan(const World& world, const SimTrajectory& ego, double t, std::uint64_t seed, std::uint64_t frame,
                const ScanningOptions& options, PolarScan& scan);

struct SequenceSummary {
  std::size_t frames = 0;
  double duration = 0.0;  ///< s simulated
  double distance = 0.0;  ///< m driven
  double seconds = 0.0;   ///< wall time
};

/// Writes an Oxford-layout sequence into `dir`: radar/<stamp>.png, radar.timestamps,
/// gt/radar_odometry.csv (Oxford axes; as in the dataset, source_ and destination_timestamp lie half
/// a sweep after the scans' source_ and destination_radar_timestamp), and gt/poses.txt (KITTI, vehicle frame, z up,
/// first pose identity, one line a scan: a convenience for radar_eval). Scan timestamps mark the sweep's first azimuth
/// (as in Oxford); azimuth a is taken at stamp + a · period / azimuths.
SequenceSummary writeScanningSequence(const std::string& dir, const SimTrajectory& ego, const WorldOptions& world,
                                      const ScanningOptions& options, const SequenceOptions& sequence);

/// The Boreas layout's extras: where the scene lies in ENU and the radar it imitates.
struct BoreasLayoutOptions {
  /// Added to every position of applanix/radar_poses.csv (the simulator works near the origin;
  /// the dataset's ENU positions are UTM-sized).
  double enu_east = 0.0, enu_north = 0.0;
  /// Write the flag byte as alternating chirp types (255 up, 0 down, as 2024 scans) instead of
  /// validity flags, and shift each azimuth's ranges as its chirp does.
  bool chirp_flags = false;
  /// FMCW range-Doppler coupling (s): with chirp flags, an up-chirp azimuth shows a scatterer whose
  /// radial velocity is v_r (positive receding) at r + β·v_r, a down-chirp one at r − β·v_r
  /// (β = carrier frequency / chirp slope). The simulator's scatterers are static, so v_r is the
  /// sensor's own velocity along the beam, negated. 0: no shift.
  double chirp_beta = 0.049;
  /// Write applanix/imu.csv: a gyro with these errors (imu_model.h) from a second before the first
  /// sweep to a second after the last (within the trajectory).
  bool imu = false;
  ImuOptions imu_options;
};

/// Shifts each azimuth of `scan` by ±β·v_r as its chirp type says (BoreasLayoutOptions), v_r the
/// radial velocity of static scenery along that azimuth at its row's time `t0 + (stamp_us −
/// stamp0_us)`, resampled linearly along the range bins.
void applyChirpShift(PolarScan& scan, const SimTrajectory& ego, double t0, std::int64_t stamp0_us, double beta);

/// Writes a Boreas-layout sequence into `dir`, as the dataset lays it out: radar/<stamp>.png, each
/// named by its row 199's timestamp (floor(M / 2) − 1: the sweep's middle, which is at trajectory
/// pose `start + k`), and applanix/radar_poses.csv, the radar's pose at each scan in the dataset's
/// frames and units (ENU; the radar's x forward, y right, z down, roll π; GPSTime in ns), with
/// applanix/imu.csv when `layout.imu`, and gt/poses.txt (KITTI, vehicle frame, first pose identity) as for Oxford.
/// `options` gives the bins (the reader decides their size by the scan's date, so it must match
/// `sequence.start_stamp_us`).
SequenceSummary writeBoreasSequence(const std::string& dir, const SimTrajectory& ego, const WorldOptions& world,
                                    const ScanningOptions& options, const SequenceOptions& sequence,
                                    const BoreasLayoutOptions& layout);

/// Writes a nuScenes-layout dataroot into `dir`: v1.0-sim/{sensor,calibrated_sensor,sample_data,
/// ego_pose,sample,scene,log}.json and samples|sweeps/RADAR_*/...pcd (binary, the 18-field
/// layout), one scene.
SequenceSummary writeAutomotiveSequence(const std::string& dir, const SimTrajectory& ego, const WorldOptions& world,
                                        const AutomotiveOptions& options, const SequenceOptions& sequence);

}  // namespace sim
}  // namespace radar_ndt

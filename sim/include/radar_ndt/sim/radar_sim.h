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

struct WorldOptions {
  std::uint64_t seed = 1;
  // Defaults: the automotive simulator's and the radiate profile's world; the oxford profile
  // (applyProfile) sets a denser city.
  double road_half_width_min = 4.0;  ///< m, kerb to the path's centre line
  double road_half_width_max = 8.0;
  double building_probability = 0.6;     ///< per side and 30 m block: a facade (else open land)
  double facade_gap_probability = 0.2;   ///< per 3–9 m facade piece: a gap (alleys, drives)
  double open_land_objects = 6.0;        ///< per side and open block: mean scattered buildings, bushes, cars
  double parked_car_probability = 0.35;  ///< per 6 m slot along the kerb
  double pole_spacing = 25.0;            ///< m, mean
  double tree_probability = 0.4;         ///< per 12 m slot
  double fence_probability = 0.25;       ///< per block, where there is no facade
  double hedge_probability = 0.3;        ///< per block, where there is no facade
  double movers_per_km = 12.0;           ///< moving cars and buses per km of path
  double bus_share = 0.25;
  /// 1: the mirror image of the seed's world across the path (every lateral offset and relative
  /// orientation negated, the same random draws; parked cars on the right kerb, oncoming traffic
  /// on the left). Exact on a straight path. For telling what a world's layout does from what the
  /// sensor does. The ground-clutter field is not mirrored.
  double mirror = 0.0;
  /// A city beyond the street: per side, this many more rows of building walls behind the first,
  /// `back_row_spacing` m apart (±30 %), in 5–20 m pieces with `back_row_gap_probability` gaps,
  /// drawn from their own random stream (0: none; the rest of the world is the same either way).
  double back_rows = 0.0;
  double back_row_spacing = 20.0;
  double back_row_gap_probability = 0.4;
  /// Throws std::invalid_argument naming the first setting out of range (probabilities in [0, 1],
  /// sizes positive, mirror 0 or 1).
  void validate() const;
};

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

/// Navtech CTS350-X scanning radar, Oxford Radar RobotCar layout. The defaults are the oxford
/// profile's sensor, calibrated against the real Oxford scans in the profile's world
/// (docs/simulator.md): use applyProfile(Oxford) for both; applyProfile(Radiate) gives the earlier
/// calibration against RADIATE's.
struct ScanningOptions {
  int azimuths = 400;
  int bins = 3768;
  double range_resolution = 0.0438;  ///< m per bin (the dataset's figure)
  double sweep_period = 0.25;        ///< s (4 Hz)
  int encoder_size = 5600;
  double beam_width_deg = 1.0;            ///< −3 dB, smeared across neighbouring azimuths
  int beam_rays = 7;                      ///< sub-rays across ±0.9 beam widths
  double range_psf_sigma = 0.15;          ///< m, main lobe of the range response
  double range_sidelobe_db = -32.0;       ///< range sidelobe level relative to each bin of a return
  double range_sidelobe_length = 0.5;     ///< m, exponential decay of the sidelobes
  double range_loss_db_per_decade = 0.0;  ///< power fall with range beyond 10 m
  double target_snr_db = 49.0;            ///< a facade at 10 m, normal incidence, over the noise mean
  double noise_rise_db = 0.0;             ///< noise mean grows by this much from 0 to max range
  double display_db_range = 36.0;         ///< dB spanned by 0..255
  double noise_display_level = 0.08;      ///< 0..1 value of the noise mean
  /// Compression of strong returns in the displayed power: dB over the noise mean above the knee
  /// count `display_compression` times (1: a plain log display). 0.35 above 10 dB reproduces the
  /// power distribution of the thresholded points of the real RADIATE scans.
  double display_knee_db = 55.0;
  double display_compression = 0.35;
  double speckle_looks = 2.0;  ///< target fluctuation: gamma shape (1: Rayleigh)
  /// Share of facades and vehicle sides smooth enough to mirror (chosen per surface, so a ghost
  /// is a coherent mirrored structure, not salt noise): the beam bounces off them and what it
  /// meets next appears behind the mirror, at the total path length.
  double ghost_probability = 0.3;
  double ghost_attenuation_db = 12.0;   ///< ghost power below the direct return of what it shows
  double saturation_probability = 0.0;  ///< per azimuth: a bright saturated line
  double saturation_db = 10.0;
  double leakage_db = 15.0;  ///< near-range leakage (first ~1.5 m) over the noise
  /// Diffuse ground clutter (grass, kerbs, gravel, litter): a fixed random field in the world,
  /// seen up to the first opaque surface. Mean power over the noise at 10 m of a cluttered cell;
  /// share of 1 m cells that are cluttered (bilinear between cells); Rayleigh-distributed.
  double ground_clutter_db = 8.0;
  double ground_clutter_cover = 0.0;
  double max_range = 165.0;        ///< m rendered (beyond: noise only)
  double range_offset_bins = 0.5;  ///< bin b lies at (b + offset) · resolution (Oxford 0.5, RADIATE 0)

  // What the Navtech CTS350-X of the Oxford Radar RobotCar dataset shows beyond the earlier model
  // (the radiate profile turns each off):
  /// 1: the power is stored as Navtech's counts: n = ⌊P⌋ of the linear power P in counts (the
  /// noise mean is `noise_counts`), written as ⌊20·log10 n + 0.12⌋ (0 for n < 1), so 0.5 dB a
  /// value and a coarse staircase near the floor (0, 6, 9, 12, 14, 15, 17, ...), as the real files
  /// have it; display_db_range and noise_display_level are then unused. 0: the display above.
  double display_counts = 1.0;
  double noise_counts = 2.45;   ///< mean noise power in counts (display_counts)
  double leakage_length = 0.5;  ///< m, exponential decay of the near-range leakage
  /// Antenna sidelobes in azimuth: every return also appears in the neighbouring azimuths at this
  /// level (dB, relative to its main-lobe power) decaying by exp(−|Δθ| / width); −200: none.
  double azimuth_sidelobe_db = -3.0;
  double azimuth_sidelobe_width_deg = 0.45;
  /// A second, long range tail of every return (the radial streaks behind the strongest): this
  /// many dB below each of its bins, decaying over `range_pedestal_length` m on both sides; −200:
  /// none.
  double range_pedestal_db = -70.5;
  double range_pedestal_length = 8.0;
  /// What lies behind the first opaque surface still returns this many dB below its direct power
  /// (the roof-mounted radar's vertical beam sees taller structures over nearer ones; clutter
  /// behind them too); −200: nothing is seen behind an opaque surface.
  double over_occluder_db = -15.0;
  /// Point scatterers off the road (bollards, bins, bicycles, signs, railings, window frames, the
  /// clutter of a city): `scatterer_density` a m² (0: none), at least `scatterer_clearance` m from
  /// the path, fixed per seed; each returns `scatterer_db` (dB relative to a facade at the same
  /// range) with a log-normal spread of `scatterer_sigma_db`, through the beam and range response.
  double scatterer_density = 0.16;
  double scatterer_db = -23.0;
  double scatterer_sigma_db = 9.0;
  double scatterer_clearance = 6.0;
  /// Scales every material's return depth (the range over which a surface returns).
  double depth_scale = 0.2;
  /// Throws std::invalid_argument naming the first setting out of range (sizes and lengths
  /// positive, probabilities in [0, 1], levels finite, display_compression in (0, 1]).
  void validate() const;
};

/// Sensor profiles: the scanning settings (and the kind of world) that make simulated scans look
/// like one real dataset's, measured with `radar_sim --realism` against that dataset's own scans.
///  - Oxford: the CTS350-X as the Oxford Radar RobotCar dataset recorded it (its counts display,
///    noise floor, gain by range, returns per range band, streaks), in a dense city; the default
///    for the Oxford-layout output.
///  - Radiate: the earlier calibration, against RADIATE's foggy scans (plain log display).
enum class ScanningProfile { Oxford, Radiate };
/// "oxford" or "radiate"; throws std::invalid_argument otherwise.
ScanningProfile parseScanningProfile(const std::string& name);
const char* toString(ScanningProfile profile);
/// Sets the profile's values in `world` and `scanning` (the seed, geometry and timing are left):
/// its sensor, and the world it was calibrated in (oxford: a dense city, wide streets, fewer parked
/// cars, three rows of buildings behind the facades; radiate: WorldOptions' defaults).
void applyProfile(ScanningProfile profile, WorldOptions& world, ScanningOptions& scanning);

/// ARS408-21 automotive radars with nuScenes' five mountings.
struct AutomotiveOptions {
  double period = 1.0 / 13.0;                     ///< s per sweep of each radar
  double jitter = 0.002;                          ///< s, per-sweep timing jitter
  double near_fov_deg = 60.0, near_range = 70.0;  ///< ± azimuth
  double far_fov_deg = 9.0, far_range = 200.0;
  double ray_step_deg = 0.5;
  double detection_probability = 0.35;  ///< per surface return (before merging into clusters)
  double cluster_distance = 1.0;        ///< m: returns closer than this merge into one detection
  int max_detections = 125;
  double clutter_per_sweep = 4.0;  ///< mean false detections a sweep
  double range_sigma = 0.15;       ///< m (ARS408 spec: 0.1 near … 0.4 far)
  double azimuth_sigma_deg = 0.3;  ///< (spec: 0.1° … 1°)
  double rcs_sigma_db = 3.0;
  double doppler_sigma = 0.1;       ///< m/s
  double ghost_probability = 0.05;  ///< per detection on a vehicle: a mirrored multipath ghost
  /// Throws std::invalid_argument naming the first setting out of range.
  void validate() const;
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
};

/// Shifts each azimuth of `scan` by ±β·v_r as its chirp type says (BoreasLayoutOptions), v_r the
/// radial velocity of static scenery along that azimuth at its row's time `t0 + (stamp_us −
/// stamp0_us)`, resampled linearly along the range bins.
void applyChirpShift(PolarScan& scan, const SimTrajectory& ego, double t0, std::int64_t stamp0_us, double beta);

/// Writes a Boreas-layout sequence into `dir`, as the dataset lays it out: radar/<stamp>.png, each
/// named by its row 199's timestamp (floor(M / 2) − 1: the sweep's middle, which is at trajectory
/// pose `start + k`), and applanix/radar_poses.csv, the radar's pose at each scan in the dataset's
/// frames and units (ENU; the radar's x forward, y right, z down, roll π; GPSTime in ns), with
/// gt/poses.txt (KITTI, vehicle frame, first pose identity) as for Oxford. `options` gives the bins
/// (the reader decides their size by the scan's date, so it must match `sequence.start_stamp_us`).
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

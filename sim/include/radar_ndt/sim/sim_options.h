#pragma once
// The simulator's settings (radar_sim.h): the world, the scanning sensor (with its profiles) and
// the automotive sensor, each with its field table (radar_ndt/fields.h), from which validate() and
// radar_sim's --set / --list-settings are made.

#include <cstdint>

#include "radar_ndt/fields.h"

namespace radar_ndt {
namespace sim {

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
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void WorldOptions::fields(Visit&& visit) {
  using S = WorldOptions;
  visit(&S::seed, Field("seed", "the world and noise seed: the same seed gives the same files"));
  visit(&S::road_half_width_min, Field("road_half_width_min", "m, kerb to the path's centre line (min)").atLeast(0));
  visit(&S::road_half_width_max, Field("road_half_width_max", "m, kerb to the path's centre line (max)").atLeast(0));
  visit(&S::building_probability,
        Field("building_probability", "per side and 30 m block: a facade, else open land").atLeast(0).atMost(1));
  visit(&S::facade_gap_probability,
        Field("facade_gap_probability", "per 3–9 m facade piece: a gap").atLeast(0).atMost(1));
  visit(&S::open_land_objects,
        Field("open_land_objects", "per side and open 30 m block: mean scattered buildings, bushes, cars").atLeast(0));
  visit(&S::parked_car_probability, Field("parked_car_probability", "per 6 m kerb slot").atLeast(0).atMost(1));
  visit(&S::pole_spacing, Field("pole_spacing", "m, mean spacing of lamp posts and signs").positive());
  visit(&S::tree_probability,
        Field("tree_probability", "per 12 m slot: a street tree (trunk and crown)").atLeast(0).atMost(1));
  visit(&S::fence_probability, Field("fence_probability", "per open block: a metal fence").atLeast(0).atMost(1));
  visit(&S::hedge_probability,
        Field("hedge_probability", "per open block without a fence: a hedge").atLeast(0).atMost(1));
  visit(&S::movers_per_km, Field("movers_per_km", "moving cars and buses per km of path").atLeast(0));
  visit(&S::bus_share, Field("bus_share", "share of movers that are buses").atLeast(0).atMost(1));
  visit(&S::mirror,
        Field("mirror", "1: the seed's world mirrored across the path (same draws; exact on a straight path)")
            .atLeast(0)
            .atMost(1));
  visit(&S::back_rows,
        Field("back_rows", "per side: rows of building walls behind the street's facades (0: none)").atLeast(0));
  visit(&S::back_row_spacing, Field("back_row_spacing", "m between those rows (±30 %)").positive());
  visit(&S::back_row_gap_probability,
        Field("back_row_gap_probability", "per 5–20 m piece of a back row: a gap").atLeast(0).atMost(1));
}

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
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

// Kept as one function: a table, one line a field of the sensor (the simulator's settings).
template <typename Visit>
void ScanningOptions::fields(Visit&& visit) {
  using S = ScanningOptions;
  visit(&S::azimuths, Field("azimuths", "azimuths a sweep").atLeast(1));
  visit(&S::bins, Field("bins", "range bins an azimuth").atLeast(1));
  visit(&S::range_resolution, Field("range_resolution", "m per bin").positive());
  visit(&S::sweep_period,
        Field("sweep_period", "s a sweep; azimuth a is taken at stamp + a·period/azimuths").positive());
  visit(&S::encoder_size, Field("encoder_size", "encoder counts a turn").atLeast(1));
  visit(&S::beam_width_deg, Field("beam_width_deg", "deg, −3 dB beam width (smearing across azimuths)").atLeast(0));
  visit(&S::beam_rays, Field("beam_rays", "sub-rays cast across ±0.9 beam widths").atLeast(1));
  visit(&S::range_psf_sigma, Field("range_psf_sigma", "m, σ of the range response's main lobe").atLeast(0));
  visit(&S::range_sidelobe_db, Field("range_sidelobe_db", "dB, range sidelobes relative to each bin of a return"));
  visit(&S::range_sidelobe_length, Field("range_sidelobe_length", "m, exponential decay of the sidelobes").atLeast(0));
  visit(&S::range_loss_db_per_decade,
        Field("range_loss_db_per_decade", "dB power fall per decade of range beyond 10 m"));
  visit(&S::target_snr_db, Field("target_snr_db", "dB over the noise mean of a facade at 10 m, normal incidence"));
  visit(&S::noise_rise_db, Field("noise_rise_db", "dB the noise mean grows from 0 m to max_range"));
  visit(&S::display_db_range, Field("display_db_range", "dB spanned by pixel values 0..255").positive());
  visit(&S::noise_display_level, Field("noise_display_level", "0..1 pixel value of the noise mean at 0 m"));
  visit(&S::display_knee_db,
        Field("display_knee_db", "dB over the noise mean above which display_compression applies"));
  visit(&S::display_compression,
        Field("display_compression",
              "slope of the display above the knee (1: none; 0.35 matches RADIATE's thresholded powers)")
            .positive()
            .atMost(1));
  visit(&S::speckle_looks, Field("speckle_looks", "gamma shape of target fluctuation (1: Rayleigh)").atLeast(0));
  visit(&S::ghost_probability,
        Field("ghost_probability", "share of facades and vehicle sides that mirror (multipath ghosts)")
            .atLeast(0)
            .atMost(1));
  visit(&S::ghost_attenuation_db,
        Field("ghost_attenuation_db", "dB a ghost is below the direct return of what it shows"));
  visit(&S::saturation_probability,
        Field("saturation_probability", "per azimuth: a saturated bright line").atLeast(0).atMost(1));
  visit(&S::saturation_db, Field("saturation_db", "dB over the noise of a saturated line"));
  visit(&S::leakage_db, Field("leakage_db", "dB over the noise of the near-range leakage (first ~1.5 m)"));
  visit(&S::ground_clutter_db,
        Field("ground_clutter_db", "dB over the noise at 10 m of a cluttered 1 m ground cell (Rayleigh)"));
  visit(&S::ground_clutter_cover,
        Field("ground_clutter_cover", "share of 1 m ground cells with clutter (grass, kerbs, gravel)")
            .atLeast(0)
            .atMost(1));
  visit(&S::max_range, Field("max_range", "m rendered (beyond: noise only)").positive());
  visit(&S::range_offset_bins, Field("range_offset_bins", "bin b lies at (b + offset) · range_resolution").atLeast(0));
  visit(&S::display_counts,
        Field("display_counts",
              "1: Navtech's counts, n = ⌊P⌋ stored as ⌊20·log10 n + 0.12⌋ (0.5 dB a value); 0: the display above")
            .atLeast(0));
  visit(&S::noise_counts, Field("noise_counts", "mean noise power in counts (display_counts)").positive());
  visit(&S::leakage_length, Field("leakage_length", "m, exponential decay of the near-range leakage").positive());
  visit(&S::azimuth_sidelobe_db,
        Field("azimuth_sidelobe_db", "dB, antenna sidelobes in azimuth relative to the main lobe (−200: none)"));
  visit(&S::azimuth_sidelobe_width_deg,
        Field("azimuth_sidelobe_width_deg", "deg, exponential fall of the azimuth sidelobes").positive());
  visit(&S::range_pedestal_db,
        Field("range_pedestal_db", "dB below a return of its long range tail, the radial streaks (−200: none)"));
  visit(&S::range_pedestal_length,
        Field("range_pedestal_length", "m, exponential decay of the range pedestal").positive());
  visit(&S::over_occluder_db,
        Field("over_occluder_db",
              "dB: what lies behind the first opaque surface returns this much weaker (−200: hidden)"));
  visit(&S::scatterer_density, Field("scatterer_density", "point scatterers off the road a m² (0: none)").atLeast(0));
  visit(&S::scatterer_db, Field("scatterer_db", "dB, mean scatterer strength relative to a facade at the same range"));
  visit(&S::scatterer_sigma_db,
        Field("scatterer_sigma_db", "dB, log-normal spread of the scatterer strengths").atLeast(0));
  visit(&S::scatterer_clearance,
        Field("scatterer_clearance", "m, no scatterer closer than this to the path").atLeast(0));
  visit(&S::depth_scale, Field("depth_scale", "scales every material's return depth").atLeast(0));
}

/// Sensor profiles: the scanning settings (and the kind of world) that make simulated scans look
/// like one real dataset's, measured with `radar_sim --realism` against that dataset's own scans.
///  - Oxford: the CTS350-X as the Oxford Radar RobotCar dataset recorded it (its counts display,
///    noise floor, gain by range, returns per range band, streaks), in a dense city; the default
///    for the Oxford-layout output.
///  - Radiate: the earlier calibration, against RADIATE's foggy scans (plain log display).
enum class ScanningProfile { Oxford, Radiate };
}  // namespace sim
template <>
struct EnumNames<sim::ScanningProfile> {
  static constexpr const char* what = "scanning profile";
  static constexpr EnumName<sim::ScanningProfile> names[] = {
      {sim::ScanningProfile::Oxford, "oxford", "the CTS350-X as the Oxford dataset recorded it"},
      {sim::ScanningProfile::Radiate, "radiate", "the earlier calibration to RADIATE's scans"}};
};
namespace sim {
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
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void AutomotiveOptions::fields(Visit&& visit) {
  using S = AutomotiveOptions;
  visit(&S::period, Field("period", "s between sweeps of one radar (13 Hz)").positive());
  visit(&S::jitter, Field("jitter", "s, uniform timing jitter of each sweep").atLeast(0));
  visit(&S::near_fov_deg, Field("near_fov_deg", "deg, ± azimuth of the near scan").positive());
  visit(&S::near_range, Field("near_range", "m, reach of the near scan").positive());
  visit(&S::far_fov_deg, Field("far_fov_deg", "deg, ± azimuth of the far scan"));
  visit(&S::far_range, Field("far_range", "m, reach of the far scan").positive());
  visit(&S::ray_step_deg, Field("ray_step_deg", "deg between cast rays").positive());
  visit(&S::detection_probability,
        Field("detection_probability", "per surface return, scaled by the material's RCS").atLeast(0).atMost(1));
  visit(&S::cluster_distance,
        Field("cluster_distance", "m: returns closer than this merge into one detection").atLeast(0));
  visit(&S::max_detections, Field("max_detections", "detections a sweep (strongest kept)").atLeast(1));
  visit(&S::clutter_per_sweep, Field("clutter_per_sweep", "mean false detections a sweep (random Doppler)").atLeast(0));
  visit(&S::range_sigma, Field("range_sigma", "m, range noise (doubled in the far scan)").atLeast(0));
  visit(&S::azimuth_sigma_deg, Field("azimuth_sigma_deg", "deg, azimuth noise at boresight (×2 at ±60°)").atLeast(0));
  visit(&S::rcs_sigma_db, Field("rcs_sigma_db", "dB, RCS noise").atLeast(0));
  visit(&S::doppler_sigma, Field("doppler_sigma", "m/s, Doppler noise").atLeast(0));
  visit(&S::ghost_probability, Field("ghost_probability", "per detection on a vehicle: a multipath ghost")
                                   .atLeast(0)
                                   .atMost(1)
                                   .cli("automotive_ghost_probability"));
}

}  // namespace sim
}  // namespace radar_ndt

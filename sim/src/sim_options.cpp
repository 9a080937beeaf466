// The simulator's settings: the sensor profiles, and every options struct's validate() (each
// throws std::invalid_argument naming the struct and the setting out of range, as the library's
// options do).
#include <cmath>
#include <stdexcept>
#include <string>

#include "radar_ndt/sim/radar_sim.h"
#include "radar_ndt/sim/synthetic_scan.h"

namespace radar_ndt {
namespace sim {
namespace {

/// Checks settings of one struct: each names itself in the error.
class Checker {
 public:
  explicit Checker(const char* owner) : owner_(owner) {}
  void positive(double v, const char* name) const {
    if (!(v > 0) || !std::isfinite(v)) fail(name, "must be > 0 and finite", v);
  }
  void nonNegative(double v, const char* name) const {
    if (!(v >= 0) || !std::isfinite(v)) fail(name, "must be >= 0 and finite", v);
  }
  void probability(double v, const char* name) const {
    if (!(v >= 0 && v <= 1)) fail(name, "must be a probability in [0, 1]", v);
  }
  void finite(double v, const char* name) const {
    if (!std::isfinite(v)) fail(name, "must be finite", v);
  }
  void atLeast(double v, double least, const char* name) const {
    if (!(v >= least) || !std::isfinite(v)) fail(name, ("must be >= " + std::to_string(least)).c_str(), v);
  }

 private:
  [[noreturn]] void fail(const char* name, const char* what, double v) const {
    throw std::invalid_argument(std::string(owner_) + ": " + name + " " + what + ", got " + std::to_string(v));
  }
  const char* owner_;
};

}  // namespace

void WorldOptions::validate() const {
  const Checker c("WorldOptions");
  c.nonNegative(road_half_width_min, "road_half_width_min");
  c.atLeast(road_half_width_max, road_half_width_min, "road_half_width_max");
  for (const auto& [v, name] : {std::pair{building_probability, "building_probability"},
                                {facade_gap_probability, "facade_gap_probability"},
                                {parked_car_probability, "parked_car_probability"},
                                {tree_probability, "tree_probability"},
                                {fence_probability, "fence_probability"},
                                {hedge_probability, "hedge_probability"},
                                {bus_share, "bus_share"},
                                {back_row_gap_probability, "back_row_gap_probability"}})
    c.probability(v, name);
  c.nonNegative(open_land_objects, "open_land_objects");
  c.positive(pole_spacing, "pole_spacing");
  c.nonNegative(movers_per_km, "movers_per_km");
  if (mirror != 0.0 && mirror != 1.0) throw std::invalid_argument("WorldOptions: mirror must be 0 or 1");
  c.nonNegative(back_rows, "back_rows");
  c.positive(back_row_spacing, "back_row_spacing");
}

void ScanningOptions::validate() const {
  const Checker c("ScanningOptions");
  c.atLeast(azimuths, 1, "azimuths");
  c.atLeast(bins, 1, "bins");
  c.positive(range_resolution, "range_resolution");
  c.positive(sweep_period, "sweep_period");
  c.atLeast(encoder_size, 1, "encoder_size");
  c.nonNegative(beam_width_deg, "beam_width_deg");
  c.atLeast(beam_rays, 1, "beam_rays");
  c.nonNegative(range_psf_sigma, "range_psf_sigma");
  for (const auto& [v, name] : {std::pair{range_sidelobe_db, "range_sidelobe_db"},
                                {range_loss_db_per_decade, "range_loss_db_per_decade"},
                                {target_snr_db, "target_snr_db"},
                                {noise_rise_db, "noise_rise_db"},
                                {display_knee_db, "display_knee_db"},
                                {ghost_attenuation_db, "ghost_attenuation_db"},
                                {saturation_db, "saturation_db"},
                                {leakage_db, "leakage_db"},
                                {ground_clutter_db, "ground_clutter_db"},
                                {azimuth_sidelobe_db, "azimuth_sidelobe_db"},
                                {range_pedestal_db, "range_pedestal_db"},
                                {over_occluder_db, "over_occluder_db"},
                                {scatterer_db, "scatterer_db"},
                                {noise_display_level, "noise_display_level"}})
    c.finite(v, name);
  c.nonNegative(range_sidelobe_length, "range_sidelobe_length");
  c.positive(display_db_range, "display_db_range");
  if (!(display_compression > 0 && display_compression <= 1))
    throw std::invalid_argument("ScanningOptions: display_compression must be in (0, 1]");
  c.nonNegative(speckle_looks, "speckle_looks");
  c.probability(ghost_probability, "ghost_probability");
  c.probability(saturation_probability, "saturation_probability");
  c.probability(ground_clutter_cover, "ground_clutter_cover");
  c.positive(max_range, "max_range");
  c.nonNegative(range_offset_bins, "range_offset_bins");
  c.nonNegative(display_counts, "display_counts");
  c.positive(noise_counts, "noise_counts");
  c.positive(leakage_length, "leakage_length");
  c.positive(azimuth_sidelobe_width_deg, "azimuth_sidelobe_width_deg");
  c.positive(range_pedestal_length, "range_pedestal_length");
  c.nonNegative(scatterer_density, "scatterer_density");
  c.nonNegative(scatterer_sigma_db, "scatterer_sigma_db");
  c.nonNegative(scatterer_clearance, "scatterer_clearance");
  c.nonNegative(depth_scale, "depth_scale");
}

void AutomotiveOptions::validate() const {
  const Checker c("AutomotiveOptions");
  c.positive(period, "period");
  c.nonNegative(jitter, "jitter");
  c.positive(near_fov_deg, "near_fov_deg");
  c.positive(near_range, "near_range");
  c.nonNegative(far_fov_deg, "far_fov_deg");
  c.positive(far_range, "far_range");
  c.positive(ray_step_deg, "ray_step_deg");
  c.probability(detection_probability, "detection_probability");
  c.nonNegative(cluster_distance, "cluster_distance");
  c.atLeast(max_detections, 1, "max_detections");
  c.nonNegative(clutter_per_sweep, "clutter_per_sweep");
  c.nonNegative(range_sigma, "range_sigma");
  c.nonNegative(azimuth_sigma_deg, "azimuth_sigma_deg");
  c.nonNegative(rcs_sigma_db, "rcs_sigma_db");
  c.nonNegative(doppler_sigma, "doppler_sigma");
  c.probability(ghost_probability, "ghost_probability");
}

void SequenceOptions::validate() const {
  if (png_compression < 0 || png_compression > 9)
    throw std::invalid_argument("SequenceOptions: png_compression must be a zlib level 0..9, got " +
                                std::to_string(png_compression));
  if (scene_name.empty()) throw std::invalid_argument("SequenceOptions: scene_name must not be empty");
}

// ---- sensor profiles --------------------------------------------------------------------------

ScanningProfile parseScanningProfile(const std::string& name) {
  if (name == "oxford") return ScanningProfile::Oxford;
  if (name == "radiate") return ScanningProfile::Radiate;
  throw std::invalid_argument("unknown scanning profile '" + name + "' (oxford or radiate)");
}

const char* toString(ScanningProfile profile) {
  return profile == ScanningProfile::Oxford ? "oxford" : "radiate";
}

void applyProfile(ScanningProfile profile, WorldOptions& w, ScanningOptions& s) {
  // The world and sensor settings a profile owns; the seed, geometry and timing stay.
  const std::uint64_t seed = w.seed;
  w = WorldOptions();
  w.seed = seed;
  const ScanningOptions kept = s;
  s = ScanningOptions();
  s.azimuths = kept.azimuths;
  s.bins = kept.bins;
  s.range_resolution = kept.range_resolution;
  s.range_offset_bins = kept.range_offset_bins;
  s.sweep_period = kept.sweep_period;
  s.encoder_size = kept.encoder_size;
  s.max_range = kept.max_range;
  if (profile == ScanningProfile::Oxford) {
    // The sensor: ScanningOptions' defaults. The world it was calibrated in: a dense city.
    w.road_half_width_min = 3.0;
    w.road_half_width_max = 14.0;
    w.building_probability = 0.8;
    w.parked_car_probability = 0.2;
    w.back_rows = 3.0;
    return;
  }
  // Radiate: the earlier calibration against RADIATE's foggy scans (plain log display), in
  // WorldOptions' default world.
  s.beam_width_deg = 2.0;
  s.range_psf_sigma = 0.12;
  s.range_sidelobe_db = -30.0;
  s.range_sidelobe_length = 1.0;
  s.range_loss_db_per_decade = 10.0;
  s.target_snr_db = 30.0;
  s.noise_rise_db = 3.5;
  s.display_knee_db = 10.0;
  s.display_compression = 1.0;
  s.saturation_probability = 0.002;
  s.leakage_db = 34.0;
  s.ground_clutter_cover = 0.4;
  s.display_counts = 0.0;
  s.azimuth_sidelobe_db = -200.0;
  s.range_pedestal_db = -200.0;
  s.over_occluder_db = -200.0;
  s.scatterer_density = 0.0;
  s.depth_scale = 1.0;
}

}  // namespace sim

void SyntheticScanOptions::validate() const {
  const sim::Checker c("SyntheticScanOptions");
  c.atLeast(static_cast<double>(points), 1, "points");
  c.positive(extent, "extent");
  c.nonNegative(noise_std, "noise_std");
  c.probability(clutter_fraction, "clutter_fraction");
  c.nonNegative(clutter_power_max, "clutter_power_max");
  c.nonNegative(max_translation, "max_translation");
  c.nonNegative(max_rotation_deg, "max_rotation_deg");
}

}  // namespace radar_ndt

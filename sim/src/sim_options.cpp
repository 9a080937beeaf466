// The simulator's settings: the sensor profiles, and every options struct's validate() (each
// throws std::invalid_argument naming the struct and the setting out of range, from the field
// tables in radar_sim.h, as the library's options do).
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
  checkFields(*this, "WorldOptions");
  if (!(road_half_width_max >= road_half_width_min))
    throw std::invalid_argument("WorldOptions: road_half_width_max must be >= road_half_width_min");
  if (mirror != 0.0 && mirror != 1.0) throw std::invalid_argument("WorldOptions: mirror must be 0 or 1");
}

void ScanningOptions::validate() const {
  checkFields(*this, "ScanningOptions");
}

void AutomotiveOptions::validate() const {
  checkFields(*this, "AutomotiveOptions");
}

void SequenceOptions::validate() const {
  if (png_compression < 0 || png_compression > 9)
    throw std::invalid_argument("SequenceOptions: png_compression must be a zlib level 0..9, got " +
                                std::to_string(png_compression));
  if (scene_name.empty()) throw std::invalid_argument("SequenceOptions: scene_name must not be empty");
}

// ---- sensor profiles --------------------------------------------------------------------------

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

#pragma once
// Up- and down-chirp range shifts of scanning radars that alternate chirps (Boreas from 2024).
//
// An FMCW radar measures range from a beat frequency that the Doppler shift moves: an up-chirp
// shows a scatterer receding at v_r (m/s) at r + β·v_r, a down-chirp at r − β·v_r (β, in s, is
// the carrier frequency over the chirp slope). For static scenery v_r is minus the sensor's
// velocity along the beam, so with the radar's velocity v (vehicle frame) the scenery of azimuth θ
// is displaced by s·g(θ), g(θ) = −(u_x cos θ + u_y sin θ), u = β·v, s = +1 for an up-chirp and −1
// for a down-chirp. Alternating azimuths are displaced in opposite directions, so structures split
// into two and move with the bearing: the matcher sees a different distortion in every scan.
//
// Neither β nor v is needed: two neighbouring azimuths see nearly the same scenery through
// opposite chirps, so their relative shift along range, found by cross-correlating the two rows,
// is 2·g(θ). estimateChirpShift fits u to those shifts over every neighbouring pair (least squares,
// then again without the outliers), and correctChirpShift moves each row back by −s·g(θ).

#include <Eigen/Core>

#include "radar_ndt/fields.h"
#include "radar_ndt/io/polar_scan.h"

namespace radar_ndt {

struct ChirpCorrectionOptions {
  bool enabled = true;      ///< correct scans that carry chirp types (PolarScan::chirp_up)
  double max_shift = 3.0;   ///< m: the largest |g| searched (β 0.05 s at 60 m/s)
  double min_range = 5.0;   ///< m: the bins compared, past the radar's own near-range leakage
  double max_range = 80.0;  ///< m
  double top_share = 0.05;  ///< the strongest share of a row's compared bins correlated against its neighbour
  int min_pairs = 40;       ///< neighbouring pairs with a clear peak a fit needs
  double min_peak = 0.3;    ///< normalised correlation a pair's peak must reach to count
  /// Throws std::invalid_argument naming the setting out of range.
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void ChirpCorrectionOptions::fields(Visit&& visit) {
  using S = ChirpCorrectionOptions;
  visit(&S::enabled, Field("enabled", "undo the up/down-chirp range shifts of scans with chirp types")
                         .offSwitch("no-chirp-correction",
                                    "leave the up/down-chirp range shifts of scans "
                                    "with chirp types (boreas, 2024) as they are"));
  visit(&S::max_shift, Field("max_shift", "the largest shift searched").unit("m").positive());
  visit(&S::min_range, Field("min_range", "the bins compared start here").unit("m").atLeast(0));
  visit(&S::max_range, Field("max_range", "... and end here").unit("m").positive());
  visit(&S::top_share, Field("top_share", "the strongest share of a row's bins correlated").positive().atMost(1));
  visit(&S::min_pairs, Field("min_pairs", "neighbouring pairs with a clear peak a fit needs").atLeast(2));
  visit(&S::min_peak, Field("min_peak", "normalised correlation a pair's peak must reach").atLeast(0).below(1));
}

struct ChirpShiftEstimate {
  bool valid = false;
  Eigen::Vector2d u = Eigen::Vector2d::Zero();  ///< β·v (m) in the vehicle frame
  int pairs = 0;                                ///< pairs the fit kept
  double rms = 0.0;                             ///< m, residual of the kept pairs
};

/// u from the relative shifts of neighbouring up/down azimuths; invalid for a scan without chirp
/// types or with fewer than `min_pairs` clear pairs (a scan of open land, say).
ChirpShiftEstimate estimateChirpShift(const PolarScan& scan, const ChirpCorrectionOptions& options = {});

/// Undoes the displacement s·g(θ) of each azimuth for u (a no-op without chirp types), in the bins
/// up to `max_range` (m; the rest of each row is left as it was: for a front-end that reads no
/// farther).
void correctChirpShift(PolarScan& scan, const Eigen::Vector2d& u, double max_range = 1e300);

/// Both, when `options.enabled` and the scan has chirp types; returns the estimate (invalid:
/// nothing was changed).
ChirpShiftEstimate correctChirps(PolarScan& scan, const ChirpCorrectionOptions& options = {}, double max_range = 1e300);

}  // namespace radar_ndt

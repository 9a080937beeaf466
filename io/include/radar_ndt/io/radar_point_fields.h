#pragma once
// A point-cloud radar's detections as named fields (a PCD file's columns, a ROS PointCloud2's
// fields) turned into PointRadar in the sensor frame. What the fields are called, how Doppler and
// accuracy are given and which detections are kept is a radar's description (sensor_description.h);
// the nuScenes PCD reader is this conversion with the ARS408's description.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <pcl/point_cloud.h>

#include "radar_ndt/point_types.h"

namespace radar_ndt {

/// How a radar reports its Doppler (radial) velocity.
enum class DopplerKind {
  None,        ///< no Doppler: the automotive pipeline needs it, a description without it is refused there
  Radial,      ///< one field, the radial velocity
  Components,  ///< two fields, the target's velocity (vx, vy) in the sensor frame; radial = its part along the ray
};

/// How a radar reports each detection's position accuracy.
enum class AccuracyKind {
  Model,      ///< nothing per point: the front-end's data-sheet model (frontend/point_covariance.h)
  Ars408Rms,  ///< per-point ARS408 accuracy state indices (nuScenes' x_rms, y_rms), ars408RmsValue
  RmsFields,  ///< per-point standard deviations in metres along the sensor's x and y
  Fixed,      ///< the same standard deviations (m) for every point, along the sensor's x and y
};

/// A 4D radar's accuracy as 1σ in its own spherical coordinates (range m, azimuth and elevation
/// deg): what the 6-DoF pipeline's point covariances come from (frontend/point_covariance.h,
/// sphericalCovariance). The planar pipelines do not read it.
struct SphericalSigmas {
  double range = 0, azimuth_deg = 0, elevation_deg = 0;
};

/// Which of a radar's fields hold what, and which detections are kept.
struct RadarPointFields {
  std::string x = "x", y = "y", z = "z";  ///< z may be absent from the data (then 0)
  DopplerKind doppler = DopplerKind::Components;
  std::string radial;                ///< DopplerKind::Radial: its field
  double radial_sign = 1.0;          ///< +1: positive when the target recedes (PointRadar's); −1: when it approaches
  std::string vx = "vx", vy = "vy";  ///< DopplerKind::Components: their fields
  std::string rcs;                   ///< radar cross section (dBsm); empty: none
  std::string power;                 ///< the matcher's weight (eq. 1); empty: 1 for every detection, as the paper
  AccuracyKind accuracy = AccuracyKind::Model;
  std::string accuracy_x, accuracy_y;        ///< Ars408Rms, RmsFields: their fields
  double sigma_x = 0.0, sigma_y = 0.0;       ///< Fixed: metres
  std::optional<SphericalSigmas> spherical;  ///< `spherical_accuracy:`; none: the run's setting
  /// `time:` each detection's measurement time relative to its message's stamp (a driver's per-point
  /// time), read into time_offset (s) as the field's value times `time_scale`; empty: none (0).
  std::string time;
  double time_scale = 1.0;
  double max_range = 150.0;  ///< detections beyond it dropped (m)
  /// Detections kept only when each listed field's value (rounded to an integer) is one of its
  /// values; a field the data lacks keeps every detection.
  std::vector<std::pair<std::string, std::vector<int>>> keep;
  /// Detections whose Doppler is used (the ego-velocity fit, the moving-detection test, Doppler
  /// weights) only when each listed field's value is one of its values; the others keep their
  /// position for the map and the match, their `doppler` NaN (a radar's ambiguous Doppler says
  /// nothing about where the reflector is). A field the data lacks leaves every Doppler used.
  std::vector<std::pair<std::string, std::vector<int>>> keep_doppler;

  /// The fields read, in the order convertRadarPoints takes their columns: x, y, z, then the
  /// Doppler, rcs, power, accuracy and time fields that are named, then the keep filters', then the
  /// keep_doppler filters'.
  std::vector<std::string> columns() const;
  /// The fields the data must have: x, y, the Doppler fields and the time field when named.
  std::vector<std::string> requiredColumns() const;
};

struct RadarPointStats {
  std::size_t points_in_data = 0;
  std::size_t kept = 0;
  std::size_t dropped_by_filter = 0;
  std::size_t dropped_non_finite = 0;  ///< NaN or Inf coordinates, velocities or times
  std::size_t doppler_unused = 0;      ///< kept, their Doppler NaN (keep_doppler)
};

/// Converts `n` detections given as a row-major table of doubles, one row a detection and one
/// column for each of `fields.columns()`, into PointRadar in
/// the sensor frame: x y z, `doppler` positive when the target recedes, `rcs`, `power`, the
/// covariance diagonal from the accuracy (0 for AccuracyKind::Model, and where a point's accuracy is
/// invalid), `time_offset` from the time field (0 without one), `sensor_id`. Detections with
/// non-finite coordinates, Doppler or time are dropped and counted;
/// those whose Doppler keep_doppler refuses get `doppler` NaN.
/// `present[c]` says whether the data has column c at all (a missing z is 0, a missing filter
/// field keeps every detection; the required columns must be present).
pcl::PointCloud<PointRadar> convertRadarPoints(const std::vector<double>& table, std::size_t n,
                                               const std::vector<char>& present, const RadarPointFields& fields,
                                               std::uint16_t sensor_id, RadarPointStats* stats = nullptr);

}  // namespace radar_ndt

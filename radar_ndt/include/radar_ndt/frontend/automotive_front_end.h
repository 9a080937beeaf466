#pragma once
// The automotive front-end: a radar cycle (io/radar_cycle.h) into one cloud in the vehicle frame
// at the reference time: point covariances, Doppler ego-velocity, moving detections removed,
// sweeps compensated to the reference time.

#include <cstdint>
#include <string>
#include <vector>

#include <pcl/point_cloud.h>

#include "radar_ndt/fields.h"
#include "radar_ndt/frontend/doppler_outlier_removal.h"
#include "radar_ndt/frontend/ego_velocity.h"
#include "radar_ndt/frontend/point_covariance.h"
#include "radar_ndt/io/radar_cycle.h"
#include "radar_ndt/point_types.h"

namespace radar_ndt {

/// A cycle after the front-end: one cloud in the vehicle frame at the reference time, planar
/// (z = 0: the sensors' mounting height is not an elevation measurement).
struct ProcessedCycle {
  std::int64_t timestamp_us = 0;
  pcl::PointCloud<PointRadar>::Ptr cloud{new pcl::PointCloud<PointRadar>};
  EgoVelocity ego;
  std::vector<SensorMounting> mountings;  ///< by sensor_id, for Doppler predictions downstream
  std::size_t raw_points = 0;             ///< detections read (after the reader's filters)
  std::size_t removed_moving = 0;         ///< removed by the Doppler outlier filter
};

struct AutomotiveFrontEndOptions {
  PointCovarianceModel covariance_model = PointCovarianceModel::Polar;
  PolarAccuracy polar;
  EgoVelocityOptions ego_velocity;
  /// Remove detections that disagree with the ego-velocity (Kellner's RANSAC outliers).
  bool remove_moving = true;
  /// Move each sweep to the reference time with the ego-velocity (constant over the cycle).
  bool compensate_time = true;
  /// Throws std::invalid_argument naming the setting out of range.
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void AutomotiveFrontEndOptions::fields(Visit&& visit) {
  using S = AutomotiveFrontEndOptions;
  visit(&S::covariance_model, Field("covariance_model", "each detection's covariance").cli("covariance"));
  visit(&S::polar, Field("polar", "the data sheet's accuracies (covariance model polar)"));
  visit(&S::ego_velocity, Field("ego_velocity", "the Doppler ego-velocity"));
  visit(&S::remove_moving, Field("remove_moving", "remove detections that disagree with the ego-velocity")
                               .offSwitch("keep-moving",
                                          "do not remove detections that disagree with "
                                          "the Doppler ego-velocity (ablation)"));
  visit(&S::compensate_time,
        Field("compensate_time", "move each radar's sweep to the reference time")
            .offSwitch("no-time-compensation", "do not move each radar's sweep to the reference time (ablation)"));
}

class AutomotiveFrontEnd {
 public:
  AutomotiveFrontEnd() = default;
  /// Validates `o` (std::invalid_argument).
  explicit AutomotiveFrontEnd(const AutomotiveFrontEndOptions& o) : options_(o) { options_.validate(); }
  const AutomotiveFrontEndOptions& options() const { return options_; }

  /// When the ego-velocity of this cycle cannot be estimated (too few stationary detections),
  /// `fallback` (e.g. the previous cycle's) is used for the filter and the time compensation, and
  /// the result's ego.valid stays false.
  ProcessedCycle process(const RadarCycle& cycle, const EgoVelocity* fallback = nullptr) const;

 private:
  AutomotiveFrontEndOptions options_;
};

}  // namespace radar_ndt

#pragma once
// A nuScenes-layout scene as a sequence of radar cycles (docs/automotive_pipeline.md): the
// reference radar (default: the forward-facing one) clocks the cycles; each other radar gives its
// latest sweep within one period before the reference sweep. The pose of cycle k is the vehicle
// frame at its reference sweep's timestamp; ground truth is the ego pose of that sweep.

#include <string>
#include <vector>

#include "radar_ndt/fields.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/io/radar_cycle.h"
#include "radar_ndt/io/trajectory_io.h"

namespace radar_ndt {

struct NuScenesSequenceOptions {
  NuScenesRadarFilter filter;
  /// Channel that clocks the cycles; empty: the radar mounted closest to straight ahead.
  std::string reference_channel;
  /// Radar channels used (names from sensor.json); empty: every radar channel. A car with one
  /// radar is one channel (its ego-velocity then takes the nonholonomic model, EgoVelocityModel).
  std::vector<std::string> channels;
  /// Throws std::invalid_argument naming the setting out of range.
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void NuScenesSequenceOptions::fields(Visit&& visit) {
  using S = NuScenesSequenceOptions;
  visit(&S::filter, Field("filter", "the detections read"));
  visit(&S::reference_channel,
        Field("reference_channel", "the radar channel that clocks the cycles (empty: the forward-facing one)")
            .cli("reference-channel"));
  visit(&S::channels, Field("channels",
                            "the radar channels used (empty: every radar in sensor.json); one channel "
                            "runs a one-radar car")
                          .cli("channels"));
}

class NuScenesRadarSequence : public RadarCycleSource {
 public:
  NuScenesRadarSequence(const NuScenesDataset& dataset, const NuScenesScene& scene,
                        const NuScenesSequenceOptions& options = {});

  const std::string& sceneName() const override { return scene_name_; }
  const std::string& referenceChannel() const override { return reference_channel_; }
  double periodSeconds() const override { return period_s_; }
  std::size_t size() const override { return plans_.size(); }
  std::size_t sweepCount() const { return sweeps_.size(); }

  std::int64_t timestamp(std::size_t k) const override { return sweeps_[plans_[k].reference].timestamp_us; }
  /// Ego pose (vehicle to global) at cycle k's reference sweep.
  const Eigen::Isometry3d& groundTruth(std::size_t k) const { return sweeps_[plans_[k].reference].ego_to_global; }
  /// Ground truth of all cycles as a TUM trajectory (stamps in seconds) projected to SE(2)
  /// (x, y, yaw) and made relative to the first cycle: what an SE(2) odometry is compared with.
  Trajectory groundTruthTrajectory() const override;

  /// Radars that fell silent within the scene: one line for each gap of more than three of that
  /// radar's own median intervals between sweeps, naming the channel, its length and its times (an
  /// empty sweep is data; no sweep at all is a silence).
  const std::vector<std::string>& silences() const override { return silences_; }

  /// Reads cycle k's sweeps. A sweep that cannot be read (missing, truncated, malformed file) is
  /// left out and described in `problems` (file and reason); the cycle goes on with the others.
  RadarCycle load(std::size_t k, std::vector<std::string>* problems = nullptr,
                  std::size_t* non_finite_dropped = nullptr) const override;

 private:
  std::string scene_name_;
  std::string reference_channel_;
  double period_s_ = 0;
  NuScenesSequenceOptions options_;
  std::vector<NuScenesSweep> sweeps_;
  std::vector<CyclePlan> plans_;
  std::vector<std::string> silences_;
};

}  // namespace radar_ndt

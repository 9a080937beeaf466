#include "radar_ndt/io/nuscenes_sequence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

namespace {
/// "A, B, C": for messages that list the channels there are.
template <typename Range, typename Name>
std::string joinNames(const Range& range, Name name) {
  std::string names;
  for (const auto& item : range) names += (names.empty() ? "" : ", ") + name(item);
  return names;
}
}  // namespace

void NuScenesSequenceOptions::validate() const {
  checkFields(*this, "NuScenesSequenceOptions");
}

namespace {

/// The sweeps of the chosen channels (all when none is chosen); a channel the dataset does not
/// have, or none left, is an error naming the channels there are.
void keepChannels(std::vector<NuScenesSweep>& sweeps, const std::vector<std::string>& channels,
                  const std::vector<std::string>& chosen, const std::string& scene) {
  if (chosen.empty()) return;
  std::vector<char> wanted(channels.size(), 0);
  for (const auto& name : chosen) {
    std::size_t i = 0;
    while (i < channels.size() && channels[i] != name) ++i;
    if (i == channels.size())
      throw std::invalid_argument("no radar channel '" + name + "' (radar channels: " +
                                  joinNames(channels, [](const std::string& c) { return c; }) + ")");
    wanted[i] = 1;
  }
  std::vector<NuScenesSweep> kept;
  for (auto& s : sweeps)
    if (s.channel_index < wanted.size() && wanted[s.channel_index]) kept.push_back(std::move(s));
  sweeps.swap(kept);
  if (sweeps.empty()) throw std::invalid_argument("scene " + scene + " has no sweeps of the chosen radar channels");
}

}  // namespace

NuScenesRadarSequence::NuScenesRadarSequence(const NuScenesDataset& dataset, const NuScenesScene& scene,
                                             const NuScenesSequenceOptions& options)
    : scene_name_(scene.name), options_(options), sweeps_(dataset.radarSweeps(scene)) {
  options_.validate();
  if (sweeps_.empty()) throw std::invalid_argument("scene " + scene.name + " has no radar sweeps");
  const auto& channels = dataset.radarChannels();
  keepChannels(sweeps_, channels, options.channels, scene.name);
  std::map<std::uint16_t, SensorMounting> mountings;
  for (const auto& s : sweeps_)
    if (!mountings.count(s.channel_index)) mountings[s.channel_index] = toMounting(s.sensor_to_ego);
  const std::uint16_t ref = chooseReferenceChannel(mountings, channels, options.reference_channel, scene.name);
  reference_channel_ = channels[ref];
  std::vector<SweepStamp> stamps;
  stamps.reserve(sweeps_.size());
  for (const auto& s : sweeps_) stamps.push_back({s.timestamp_us, s.channel_index});
  plans_ = planRadarCycles(stamps, ref);
  silences_ = findRadarSilences(stamps, channels);
  if (plans_.size() >= 2)
    period_s_ = 1e-6 * static_cast<double>(timestamp(plans_.size() - 1) - timestamp(0)) /
                static_cast<double>(plans_.size() - 1);
}

Trajectory NuScenesRadarSequence::groundTruthTrajectory() const {
  Trajectory t;
  if (plans_.empty()) return t;
  const Pose2 first = toPose2(groundTruth(0));
  for (std::size_t k = 0; k < plans_.size(); ++k) {
    t.stamps.push_back(1e-6 * static_cast<double>(timestamp(k)));
    t.poses.push_back(toIsometry3(between(first, toPose2(groundTruth(k)))));
  }
  return t;
}

RadarCycle NuScenesRadarSequence::load(std::size_t k, std::vector<std::string>* problems,
                                       std::size_t* non_finite_dropped) const {
  RadarCycle cycle;
  cycle.timestamp_us = timestamp(k);
  for (const std::size_t i : plans_[k].members) {
    const NuScenesSweep& s = sweeps_[i];
    RadarSweepData d;
    d.timestamp_us = s.timestamp_us;
    d.sensor_id = s.channel_index;
    d.sensor_to_vehicle = s.sensor_to_ego;
    try {
      NuScenesPcdStats stats;
      d.points = readNuScenesRadarPcd(s.path, options_.filter, s.channel_index, &stats);
      if (non_finite_dropped) *non_finite_dropped += stats.dropped_non_finite;
      if (problems && stats.dropped_non_finite > 0)
        problems->push_back(s.path + ": dropped " + std::to_string(stats.dropped_non_finite) +
                            " points with NaN or Inf values");
    } catch (const IoError& e) {
      if (problems) problems->push_back(e.what());
      continue;
    }
    cycle.sweeps.push_back(std::move(d));
  }
  return cycle;
}

}  // namespace radar_ndt

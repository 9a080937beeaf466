#include "node/radar_channels.h"

#include <algorithm>
#include <cstdio>
#include <map>

#include <sensor_msgs/PointCloud.h>
#include <sensor_msgs/PointCloud2.h>

namespace radar_ndt {
namespace node {

RadarChannels::RadarChannels(const SensorDescription& d, std::int64_t period_us, Handlers handlers)
    : d_(d), period_us_(period_us), on_(std::move(handlers)) {
  for (const RadarDescription& r : d_.radars) {
    channels_.emplace_back();
    channels_.back().state = TopicState(r.topic, r.name);
    if (r.mounting) channels_.back().mounting = r.mounting->transform();
  }
}

void RadarChannels::subscribe(ros::NodeHandle& nh, std::vector<ros::Subscriber>& subs) {
  for (std::size_t i = 0; i < d_.radars.size(); ++i)
    subs.push_back(nh.subscribe<topic_tools::ShapeShifter>(
        d_.radars[i].topic, 200, [this, i](const topic_tools::ShapeShifter::ConstPtr& m) { onAnyCloud(i, *m); }));
  if (allPlaced()) return;
  // Whenever they arrive: a latched /tf_static reaches the node once, at its subscription, usually
  // before any cloud names its frame.
  subs.push_back(nh.subscribe<tf2_msgs::TFMessage>("/tf", 200, [this](const auto& m) { onTf(*m, "/tf"); }));
  subs.push_back(
      nh.subscribe<tf2_msgs::TFMessage>("/tf_static", 20, [this](const auto& m) { onTf(*m, "/tf_static"); }));
}

bool RadarChannels::allPlaced() const {
  return std::all_of(channels_.begin(), channels_.end(), [](const Channel& c) { return c.mounting.has_value(); });
}

void RadarChannels::placeRadars() {
  for (std::size_t i = 0; i < d_.radars.size(); ++i) {
    Channel& c = channels_[i];
    const std::string& frame = d_.radars[i].frame.empty() ? c.frame : d_.radars[i].frame;
    if (c.mounting || frame.empty()) continue;
    c.mounting = tree_.lookup(d_.base_frame, frame, &c.unplaced);
  }
}

/// Once every radar is placed: the reference as the offline reader chooses it, and the cycles,
/// which wait for every radar as the offline planner's hold them; the sweeps held so far go in.
bool RadarChannels::startCycles() {
  if (live_) return true;
  if (!allPlaced()) return false;
  std::map<std::uint16_t, SensorMounting> m;
  std::vector<std::string> names;
  std::vector<std::uint16_t> all;
  for (std::size_t i = 0; i < d_.radars.size(); ++i) {
    names.push_back(d_.radars[i].name);
    m[static_cast<std::uint16_t>(i)] = toMounting(*channels_[i].mounting);
    all.push_back(static_cast<std::uint16_t>(i));
  }
  reference_ = chooseReferenceChannel(m, names, d_.reference, "the node's radars");
  live_ = std::make_unique<LiveCycles>(reference_, period_us_, all);
  for (RadarSweepData& s : waiting_) live_->add(std::move(s));
  waiting_.clear();
  return true;
}

void RadarChannels::onTf(const tf2_msgs::TFMessage& m, const char* topic) {
  if (allPlaced()) return;
  std::vector<std::string> bad;
  tree_.add(m, topic, &bad);
  for (const std::string& b : bad) tf_state_.problem(b);
  placeRadars();
  if (startCycles()) on_.ready();
}

void RadarChannels::onAnyCloud(std::size_t i, const topic_tools::ShapeShifter& msg) {
  const std::string& type = msg.getDataType();
  if (type == "sensor_msgs/PointCloud2") return onCloud(i, *msg.instantiate<sensor_msgs::PointCloud2>());
  if (type == "sensor_msgs/PointCloud") return onCloud(i, *msg.instantiate<sensor_msgs::PointCloud>());
  TopicState& c = channels_[i].state;
  ++c.malformed;
  c.problem(d_.radars[i].topic + ": a " + type +
            ": radar clouds are read from sensor_msgs/PointCloud2 or sensor_msgs/PointCloud: left out");
}

template <typename Msg>
void RadarChannels::onCloud(std::size_t i, const Msg& msg) {
  const ros::WallTime arrival = ros::WallTime::now();
  Channel& c = channels_[i];
  if (c.frame.empty() && !msg.header.frame_id.empty()) {
    c.frame = msg.header.frame_id;
    placeRadars();
  }
  const std::int64_t t = stampOf(d_.stamps, msg.header.stamp);
  if (c.state.arrived(t)) on_.restart(c.state, t);  // a bag played again
  on_.stamped(t, arrival);
  RadarSweepData sweep;
  sweep.timestamp_us = t;
  sweep.sensor_id = static_cast<std::uint16_t>(i);
  std::optional<pcl::PointCloud<PointRadar>> points = cloudPoints(d_.radars[i], sweep.sensor_id, msg, c.state);
  if (!points) return;
  sweep.points = std::move(*points);
  take(std::move(sweep));
}

void RadarChannels::take(RadarSweepData sweep) {
  if (!startCycles()) {
    waiting_.push_back(std::move(sweep));
    if (waiting_.size() <= kMaxWaiting) return;
    const RadarSweepData& oldest = waiting_.front();
    channels_[oldest.sensor_id].state.problem("radar " + d_.radars[oldest.sensor_id].name +
                                              " waits for a radar's mounting: its oldest waiting sweep dropped");
    const std::int64_t t = oldest.timestamp_us;
    waiting_.erase(waiting_.begin());
    if (on_.dropped) on_.dropped(t);
    return;
  }
  TopicState& state = channels_[sweep.sensor_id].state;
  const std::string& topic = d_.radars[sweep.sensor_id].topic;
  switch (live_->add(std::move(sweep))) {
    case LiveCycles::Added::Late:
      ++state.late;
      state.problem(topic + ": a sweep older than the last cycle arrived late: left out");
      break;
    case LiveCycles::Added::Repeated:  // as the offline reader leaves a repeated stamp out
      ++state.late;
      state.problem(topic + ": a second sweep at the same stamp: left out");
      break;
    case LiveCycles::Added::Taken: break;
  }
  on_.ready();
}

std::optional<RadarCycle> RadarChannels::next() {
  if (!live_) return std::nullopt;
  std::optional<RadarCycle> cycle = live_->next();
  if (cycle)
    for (RadarSweepData& s : cycle->sweeps) s.sensor_to_vehicle = *channels_[s.sensor_id].mounting;
  return cycle;
}

std::vector<RadarCycle> RadarChannels::flush() {
  if (!live_) return {};
  std::vector<RadarCycle> cycles = live_->flush();
  for (RadarCycle& cycle : cycles)
    for (RadarSweepData& s : cycle.sweeps) s.sensor_to_vehicle = *channels_[s.sensor_id].mounting;
  return cycles;
}

void RadarChannels::reset() {
  if (live_) live_->reset();
  waiting_.clear();
  for (Channel& c : channels_) c.state.last_us = -1;
}

ros::WallTime RadarChannels::lastArrival() const {
  ros::WallTime last;
  for (const Channel& c : channels_) last = std::max(last, c.state.last_arrival);
  return last;
}

std::string RadarChannels::mountingState(std::size_t i) const {
  const Channel& c = channels_[i];
  if (c.mounting) return "known";
  if (d_.radars[i].frame.empty() && c.frame.empty()) return "waiting for a cloud to name its frame";
  return c.unplaced.empty() ? "waiting for /tf_static or /tf" : c.unplaced;
}

std::vector<diagnostic_msgs::DiagnosticStatus> RadarChannels::status(const ros::WallTime& newest) const {
  std::vector<diagnostic_msgs::DiagnosticStatus> out;
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    const TopicState& s = channels_[i].state;
    out.push_back(s.status(newest,
                           s.messages == 0 ? "no cloud yet on " + s.topic + " while the other topics send"
                                           : "silent: no cloud for over a second while the other topics send",
                           {{"mounting", mountingState(i)}}));
  }
  if (!tf_state_.last_problem.empty()) out.push_back(tf_state_.status(ros::WallTime(), ""));
  return out;
}

void RadarChannels::report() const {
  for (std::size_t i = 0; i < channels_.size(); ++i)
    if (channels_[i].state.messages == 0)
      std::printf("radar_ndt_node: radar %s sent nothing on %s\n", d_.radars[i].name.c_str(),
                  d_.radars[i].topic.c_str());
    else if (!channels_[i].mounting)
      std::printf("radar_ndt_node: radar %s was never placed: %s\n", d_.radars[i].name.c_str(),
                  mountingState(i).c_str());
}

}  // namespace node
}  // namespace radar_ndt

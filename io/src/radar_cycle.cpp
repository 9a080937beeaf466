#include "radar_ndt/io/radar_cycle.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "radar_ndt/se2.h"

namespace radar_ndt {

std::vector<CyclePlan> planRadarCycles(const std::vector<SweepStamp>& sweeps, std::uint16_t reference_channel,
                                       std::int64_t period_us) {
  std::vector<std::size_t> refs;
  for (std::size_t i = 0; i < sweeps.size(); ++i)
    if (sweeps[i].channel == reference_channel) refs.push_back(i);
  if (period_us <= 0) {
    std::vector<std::int64_t> gaps;
    for (std::size_t k = 1; k < refs.size(); ++k)
      gaps.push_back(sweeps[refs[k]].timestamp_us - sweeps[refs[k - 1]].timestamp_us);
    if (gaps.empty()) {
      period_us = 1;
    } else {
      std::nth_element(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2), gaps.end());
      period_us = std::max<std::int64_t>(1, gaps[gaps.size() / 2]);
    }
  }
  std::uint16_t max_channel = 0;
  for (const auto& s : sweeps) max_channel = std::max(max_channel, s.channel);
  std::vector<CyclePlan> plans;
  plans.reserve(refs.size());
  for (const std::size_t r : refs) {
    CyclePlan plan;
    plan.reference = r;
    const std::int64_t t_ref = sweeps[r].timestamp_us;
    std::vector<long> latest(static_cast<std::size_t>(max_channel) + 1, -1);
    // Sweeps are time-ordered: walk back from the reference sweep over one period (and forward
    // over sweeps with the same timestamp).
    for (std::size_t j = r + 1; j < sweeps.size() && sweeps[j].timestamp_us == t_ref; ++j)
      if (latest[sweeps[j].channel] < 0) latest[sweeps[j].channel] = static_cast<long>(j);
    for (std::size_t j = r + 1; j-- > 0;) {
      if (sweeps[j].timestamp_us <= t_ref - period_us) break;
      if (sweeps[j].timestamp_us > t_ref) continue;
      if (latest[sweeps[j].channel] < 0) latest[sweeps[j].channel] = static_cast<long>(j);
    }
    latest[reference_channel] = static_cast<long>(r);
    for (const long j : latest)
      if (j >= 0) plan.members.push_back(static_cast<std::size_t>(j));
    plans.push_back(std::move(plan));
  }
  return plans;
}

SensorMounting toMounting(const Eigen::Isometry3d& T) {
  SensorMounting m;
  m.x = T.translation().x();
  m.y = T.translation().y();
  const Eigen::Vector3d forward = T.linear().col(0);
  m.yaw = std::atan2(forward.y(), forward.x());
  m.valid = true;
  return m;
}

std::uint16_t chooseReferenceChannel(const std::map<std::uint16_t, SensorMounting>& mountings,
                                     const std::vector<std::string>& names, const std::string& asked,
                                     const std::string& where) {
  if (!asked.empty()) {
    for (const auto& [idx, m] : mountings)
      if (idx < names.size() && names[idx] == asked) return idx;
    std::string there;
    for (const auto& e : mountings) there += (there.empty() ? "" : ", ") + names.at(e.first);
    throw std::invalid_argument("reference channel '" + asked + "' has no sweeps in " + where +
                                " (radar channels: " + there + ")");
  }
  if (mountings.empty()) throw std::invalid_argument(where + " has no radar sweeps");
  double best = 1e9;
  std::uint16_t ref = mountings.begin()->first;
  for (const auto& [idx, m] : mountings) {
    const double score = std::abs(normalizeAngle(m.yaw)) - 1e-3 * m.x;
    if (score < best) {
      best = score;
      ref = idx;
    }
  }
  return ref;
}

std::vector<std::string> findRadarSilences(const std::vector<SweepStamp>& stamps,
                                           const std::vector<std::string>& names) {
  std::vector<std::string> out;
  std::map<std::uint16_t, std::vector<std::int64_t>> by_channel;
  for (const auto& st : stamps) by_channel[st.channel].push_back(st.timestamp_us);
  for (const auto& [channel, t] : by_channel) {
    if (t.size() < 3) continue;
    std::vector<std::int64_t> gaps;
    for (std::size_t i = 1; i < t.size(); ++i) gaps.push_back(t[i] - t[i - 1]);
    std::vector<std::int64_t> sorted = gaps;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    const std::int64_t typical = sorted[sorted.size() / 2];
    for (std::size_t i = 0; i < gaps.size(); ++i)
      if (typical > 0 && gaps[i] > 3 * typical) {
        char line[256];
        std::snprintf(line, sizeof line,
                      "%s: silent for %.2f s (no sweep from %lld to %lld us; its sweeps are %.3f s apart)",
                      names.at(channel).c_str(), 1e-6 * static_cast<double>(gaps[i]), static_cast<long long>(t[i]),
                      static_cast<long long>(t[i + 1]), 1e-6 * static_cast<double>(typical));
        out.push_back(line);
      }
  }
  return out;
}

}  // namespace radar_ndt

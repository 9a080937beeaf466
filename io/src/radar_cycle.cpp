#include "radar_ndt/io/radar_cycle.h"

#include <algorithm>
#include <cmath>

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

}  // namespace radar_ndt

#include "radar_ndt/odometry/motion_compensation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace radar_ndt {

void MotionCompensationOptions::validate() const {
  checkFields(*this, "MotionCompensationOptions");
}

void compensateMotion(const pcl::PointCloud<PointRadar>& in, const Pose2& velocity, pcl::PointCloud<PointRadar>& out) {
  if (&out != &in) out = in;
  if (out.empty()) return;
  // The pose at τ, tabulated every 0.1 ms over the scan's span of time offsets (a Cartesian scan
  // has one offset per azimuth, a few hundred distinct values) instead of a sin/cos per point.
  float t_min = std::numeric_limits<float>::infinity(), t_max = -t_min;
  for (const auto& p : out)
    if (std::isfinite(p.time_offset)) {
      t_min = std::min(t_min, p.time_offset);
      t_max = std::max(t_max, p.time_offset);
    }
  if (!(t_max >= t_min)) return;  // no finite offsets
  constexpr double kStep = 1e-4;
  const std::size_t n = static_cast<std::size_t>(std::ceil((static_cast<double>(t_max) - t_min) / kStep)) + 1;
  if (n > 100000) throw std::invalid_argument("compensateMotion: time offsets span more than 10 s");
  struct Entry {
    double c, s, tx, ty;
  };
  std::vector<Entry> table(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Pose2 T = integrateVelocity(velocity, t_min + kStep * static_cast<double>(i));
    table[i] = {std::cos(T.z()), std::sin(T.z()), T.x(), T.y()};
  }
  for (auto& p : out) {
    if (!std::isfinite(p.time_offset)) continue;
    const Entry& e = table[static_cast<std::size_t>((p.time_offset - t_min) / kStep + 0.5)];  // >= 0: round
    const double c = e.c, s = e.s, x = p.x, y = p.y;
    p.x = static_cast<float>(c * x - s * y + e.tx);
    p.y = static_cast<float>(s * x + c * y + e.ty);
    // Σ' = R Σ Rᵀ
    const double xx = p.cov_xx, xy = p.cov_xy, yy = p.cov_yy;
    p.cov_xx = static_cast<float>(c * c * xx - 2 * c * s * xy + s * s * yy);
    p.cov_xy = static_cast<float>(c * s * (xx - yy) + (c * c - s * s) * xy);
    p.cov_yy = static_cast<float>(s * s * xx + 2 * c * s * xy + c * c * yy);
    p.time_offset = 0.f;
  }
}

}  // namespace radar_ndt

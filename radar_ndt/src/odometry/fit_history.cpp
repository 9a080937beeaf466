#include "radar_ndt/odometry/fit_history.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace radar_ndt {

void FitCheckOptions::validate() const {
  checkFields(*this, "FitCheckOptions");
}

bool FitHistory::accepts(double fit) const {
  if (!(options_.min_relative_fit > 0) || !std::isfinite(fit) || fits_.size() < options_.min_judged) return true;
  std::vector<double> v(fits_.begin(), fits_.end());
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return fit >= options_.min_relative_fit * v[v.size() / 2];
}

void FitHistory::add(double fit) {
  fits_.push_back(fit);
  while (fits_.size() > std::max<std::size_t>(options_.history, 1)) fits_.pop_front();
}

}  // namespace radar_ndt

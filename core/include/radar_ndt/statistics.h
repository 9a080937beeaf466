#pragma once
// The one median every part of the project takes (run timings, a sequence's scan period, a
// batch's summary, the benchmarks').

#include <algorithm>
#include <cstddef>
#include <vector>

namespace radar_ndt {

/// The median of `values`: the middle value, or for an even count the mean of the two middle
/// ones; `if_empty` when there are none.
inline double median(std::vector<double> values, double if_empty = 0.0) {
  if (values.empty()) return if_empty;
  const std::size_t n = values.size();
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(n / 2);
  std::nth_element(values.begin(), mid, values.end());
  if (n % 2 == 1) return *mid;
  const double below = *std::max_element(values.begin(), mid);
  return 0.5 * (below + *mid);
}

}  // namespace radar_ndt

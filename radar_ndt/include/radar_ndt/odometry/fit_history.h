#pragma once
// The fit check (beyond the paper): a match whose NDT score per point is far below recent
// matches' fits its target nowhere (a scan that is all noise, or one pulled along the road by a
// vehicle passing alongside) and is refused.

#include <cstddef>
#include <deque>

#include "radar_ndt/fields.h"

namespace radar_ndt {

struct FitCheckOptions {
  /// A match whose score per point is below this fraction of the median of the recent judged
  /// matches is refused. A scan that is all noise converges near the guess but fits its target
  /// nowhere, and a bus passing alongside pulls the match along the road at a fraction of the
  /// usual fit while correct matches stay near it, so this trades a rare needless
  /// constant-velocity step (a few cm off) for refusing those. 0: off.
  double min_relative_fit = 0.6;
  std::size_t history = 15;    ///< judged matches the median is taken over
  std::size_t min_judged = 5;  ///< judged matches before the check starts
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void FitCheckOptions::fields(Visit&& visit) {
  using S = FitCheckOptions;
  visit(&S::min_relative_fit,
        Field("min_relative_fit", "refuse a match fitting below this share of recent ones' median; 0: off").atLeast(0));
  visit(&S::history, Field("history", "judged matches the median is taken over").atLeast(0));
  visit(&S::min_judged,
        Field("min_judged", "judged matches before the fit check starts").atLeast(1).cli("fit-min-judged"));
}

/// The fits of the last judged matches, refused ones too: a scene that stays poorer than the last
/// (open land after a city centre) lowers the median within history / 2 scans instead of causing
/// a fallback storm, while a passing bus (a few scans) leaves the median where it was.
class FitHistory {
 public:
  explicit FitHistory(const FitCheckOptions& options = {}) : options_(options) {}
  /// Whether `fit` is at least min_relative_fit × the median of the history (always, with fewer
  /// than min_judged fits, a non-finite fit or the check off).
  bool accepts(double fit) const;
  /// Enters `fit` into the history (judge it first).
  void add(double fit);

 private:
  FitCheckOptions options_;
  std::deque<double> fits_;
};

}  // namespace radar_ndt

// FitHistory: a match that fits far worse than recent ones is refused; a scene that stays poorer
// is learned within half the history.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "radar_ndt/odometry/fit_history.h"

using namespace radar_ndt;

TEST(FitHistory, RefusesAFitBelowTheFractionOfTheRecentMedian) {
  FitHistory h;  // 0.6 of the median of 15
  for (int i = 0; i < 4; ++i) {
    EXPECT_TRUE(h.accepts(0.01)) << "fewer than 5 fits: nothing to judge by";
    h.add(1.0);
  }
  h.add(1.0);
  EXPECT_TRUE(h.accepts(0.6));
  EXPECT_FALSE(h.accepts(0.59));
  EXPECT_TRUE(h.accepts(std::numeric_limits<double>::quiet_NaN())) << "not ours: nothing to judge";
  // The median, not the mean: one outlier does not move it.
  h.add(100.0);
  EXPECT_FALSE(h.accepts(0.59));
}

TEST(FitHistory, RefusedFitsEnterTheHistorySoAPoorerSceneIsLearned) {
  FitCheckOptions o;
  o.history = 15;
  FitHistory h(o);
  for (int i = 0; i < 15; ++i) h.add(1.0);
  int refused = 0;
  for (int i = 0; i < 15; ++i) {
    const bool ok = h.accepts(0.3);
    refused += !ok;
    h.add(0.3);
  }
  EXPECT_EQ(refused, 8) << "the median turns once half the history holds the new level";
  EXPECT_TRUE(h.accepts(0.3));
}

TEST(FitHistory, OffAcceptsEverything) {
  FitCheckOptions o;
  o.min_relative_fit = 0;
  FitHistory h(o);
  for (int i = 0; i < 10; ++i) h.add(1.0);
  EXPECT_TRUE(h.accepts(1e-9));
  o.min_relative_fit = -0.1;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

TEST(FitHistory, MinJudgedSetsWhenTheCheckStarts) {
  FitCheckOptions o;
  o.min_judged = 2;
  FitHistory h(o);
  h.add(1.0);
  EXPECT_TRUE(h.accepts(0.01)) << "one fit: nothing to judge by yet";
  h.add(1.0);
  EXPECT_FALSE(h.accepts(0.01)) << "two fits judge from min_judged = 2 on";
  o.min_judged = 0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

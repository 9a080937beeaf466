// ScanningOdometry::addScan on constructed scans: motion compensation, the failure handling on a bad match
// (a bus filling the view), the fit check in a scene that turns poorer for good, and the settings
// each match runs with (the power shift s, the retry ladder, the slow grid), read off the matcher.
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "radar_ndt/odometry/motion_compensation.h"
#include "radar_ndt/odometry/scanning_odometry.h"
#include "radar_ndt/registration/weighted_ndt_2d.h"

using namespace radar_ndt;

namespace {
// A scan of a static 2D world seen from (x0, 0) within 60 m: every world point with 3 cm of
// noise, power 0.45 and a (10 cm)² covariance, in the vehicle frame.
pcl::PointCloud<PointRadar>::Ptr observeWorld(const std::vector<Eigen::Vector2d>& world, double x0, std::mt19937& rng,
                                              std::normal_distribution<float>& noise) {
  pcl::PointCloud<PointRadar>::Ptr cloud(new pcl::PointCloud<PointRadar>);
  for (const auto& w : world) {
    const double x = w.x() - x0, y = w.y();
    if (std::hypot(x, y) > 60) continue;
    PointRadar p(static_cast<float>(x) + noise(rng), static_cast<float>(y) + noise(rng), 0.f, 0.45f);
    p.cov_xx = p.cov_yy = 0.01f;
    cloud->push_back(p);
  }
  return cloud;
}

// Two facades with gaps and some poles along x.
std::vector<Eigen::Vector2d> street() {
  std::vector<Eigen::Vector2d> world;
  for (double x = -60; x <= 200; x += 0.5) {
    if (std::fmod(x + 60, 17.0) < 13.0) {
      world.emplace_back(x, 9.0);
      world.emplace_back(x, -11.0);
    }
    if (std::fmod(x + 60, 23.0) < 0.5) world.emplace_back(x, 6.5 + std::fmod(x, 3.0));
  }
  return world;
}

// Our matcher, recording the grid and the power shift every align() runs with; while `refuse` is
// set, every align() reports no convergence (a match that fails whatever the settings).
class RecordingNdt : public WeightedNDT2D<PointRadar, PointRadar> {
 public:
  struct Call {
    float grid, shift;
    bool sweep;                      // the source sweep's motion inside the match
    double sweep_dt;                 // its step, when on
    Eigen::Vector3d sweep_previous;  // and the previous scan's pose in the target's frame
  };
  std::vector<Call> calls;
  bool refuse = false;
  // With keep_clouds: each align()'s source and target as given, and its result.
  struct Match {
    pcl::PointCloud<PointRadar> source, target;
    Matrix4 result;
  };
  bool keep_clouds = false;
  std::vector<Match> matches;

 protected:
  void computeTransformation(PointCloudSource& output, const Matrix4& guess) override {
    calls.push_back({getResolution(), getPowerShift(), hasSourceSweep(), sweep_.dt, sweep_.previous});
    if (refuse) {
      converged_ = false;
      final_transformation_ = guess;
      return;
    }
    WeightedNDT2D<PointRadar, PointRadar>::computeTransformation(output, guess);
    if (keep_clouds) matches.push_back({*input_, *target_, final_transformation_});
  }
};

/// The scanning radars' nominal grid and power shift (MatcherOptions::forScanning), with the 2x2-neighbour
/// cell lookup the tests were written with.
constexpr double kScanningGrid = 3.75;
constexpr float kShift = 0.333f;

/// A matcher at kScanningGrid and kShift, as the scanning pipeline builds pw-ndt but for its cell lookup.
MatcherAdapter scanningMatcher(const std::string& method = "pw-ndt") {
  MatcherOptions o;
  o.method = method;
  o.grid = kScanningGrid;
  o.power_shift = kShift;
  return makeMatcher(o);
}

/// A RecordingNdt built with another grid and power shift than the odometry's nominal ones: the
/// adapter (atNominal) must set those.
std::shared_ptr<RecordingNdt> recordingMatcher() {
  auto r = std::make_shared<RecordingNdt>();
  WeightedNDT2DSettings s = MatcherOptions::defaultWeightedNdt();
  s.resolutions = {1.0f};
  s.power_shift = 0.05f;
  r->setSettings(s);
  r->setMaximumIterations(MatcherOptions().weighted_ndt_max_iterations);
  return r;
}

MatcherAdapter atNominal(const std::shared_ptr<RecordingNdt>& r) {
  return MatcherAdapter(r, MatchSettings{kScanningGrid, kShift});
}

// A drive down street() with the default options and a RecordingNdt, a scan every 250 ms.
struct RecordedDrive {
  explicit RecordedDrive(unsigned seed)
      : rng(seed), matcher(recordingMatcher()), odometry(options, atNominal(matcher)) {}
  // Adds scan k, seen from (x0, 0); returns the align() calls it made.
  std::vector<RecordingNdt::Call> scan(int k, double x0) {
    const std::size_t before = matcher->calls.size();
    odometry.addScan(ScanFrame{1000000 + 250000 * static_cast<std::int64_t>(k), observeWorld(world, x0, rng, noise)});
    return {matcher->calls.begin() + static_cast<std::ptrdiff_t>(before), matcher->calls.end()};
  }
  std::mt19937 rng;
  std::normal_distribution<float> noise{0.f, 0.03f};
  const std::vector<Eigen::Vector2d> world = street();
  const ScanningOdometryOptions options;
  std::shared_ptr<RecordingNdt> matcher;
  ScanningOdometry odometry;
};
}  // namespace

TEST(ScanningOdometry, EveryMatchRunsWithThePowerShiftOfTheOptions) {
  // The matcher's nominal s (eq. 1-2) and grid, whatever it was built with (recordingMatcher): every
  // match of a clean drive runs at them, and the steps record that.
  RecordedDrive d(11);
  for (int k = 0; k < 8; ++k) d.scan(k, 2.0 * k);
  ASSERT_FALSE(d.matcher->calls.empty());
  for (const auto& c : d.matcher->calls) {
    EXPECT_FLOAT_EQ(c.shift, kShift);
    EXPECT_FLOAT_EQ(c.grid, kScanningGrid);
  }
  const auto& steps = d.odometry.steps();
  for (std::size_t k = 1; k < steps.size(); ++k) {
    EXPECT_EQ(steps[k].status, StepStatus::Matched) << "step " << k;
    EXPECT_FLOAT_EQ(steps[k].power_shift, kShift) << "step " << k;
  }
  EXPECT_NEAR(steps.back().pose.x(), 14.0, 0.3);
}

TEST(ScanningOdometry, AFailedMatchClimbsTheLadderThenFallsBackToTheConstantVelocityGuess) {
  // A match that fails whatever the settings: the ladder tries every grid from g in steps of
  // grid_step until one above max_grid has failed, then the same with s halved (max_shift_halvings
  // = 1), then falls back to the constant-velocity motion; the next scan is matched at the nominal
  // settings again.
  RecordedDrive d(12);
  const ScanningOdometryOptions& o = d.options;
  std::vector<RecordingNdt::Call> ladder;
  for (const float s : {kShift, 0.5f * kShift})
    for (double g = kScanningGrid;; g += o.grid_step) {
      ladder.push_back({static_cast<float>(g), s, false, 0.0, Eigen::Vector3d::Zero()});  // grid and shift compared
      if (g > o.max_grid) break;
    }
  const int bad = 5;
  for (int k = 0; k < 8; ++k) {
    d.matcher->refuse = k == bad;
    const std::vector<RecordingNdt::Call> tried = d.scan(k, 2.0 * k);
    if (k != bad) continue;
    ASSERT_EQ(tried.size(), ladder.size());
    for (std::size_t i = 0; i < ladder.size(); ++i) {
      EXPECT_FLOAT_EQ(tried[i].grid, ladder[i].grid) << "attempt " << i;
      EXPECT_FLOAT_EQ(tried[i].shift, ladder[i].shift) << "attempt " << i;
    }
  }
  const auto& steps = d.odometry.steps();
  const OdometryStep& failed = steps[bad];
  EXPECT_EQ(failed.status, StepStatus::Fallback);
  EXPECT_EQ(failed.attempts, static_cast<int>(ladder.size()));
  EXPECT_EQ(failed.motion, failed.prior_motion) << "a failed step takes the constant-velocity guess";
  EXPECT_NEAR(failed.motion.x(), 2.0, 0.1);
  EXPECT_NEAR(failed.motion.y(), 0.0, 0.05);
  EXPECT_EQ(steps[bad + 1].status, StepStatus::Matched);
  EXPECT_FLOAT_EQ(d.matcher->calls.back().shift, kShift) << "the nominal s again after a halving";
  EXPECT_FLOAT_EQ(d.matcher->calls.back().grid, kScanningGrid);
  EXPECT_NEAR(steps.back().pose.x(), 14.0, 0.3);
}

TEST(ScanningOdometry, AStandingVehicleIsMatchedOnTheSlowGrid) {
  // Below slow_speed the grid is slow_grid (1.5 m): a vehicle standing still is matched there from
  // the third scan on (the second has no velocity yet) and stays where it is.
  RecordedDrive d(13);
  for (int k = 0; k < 8; ++k) {
    const std::vector<RecordingNdt::Call> tried = d.scan(k, 0.0);
    if (k < 2) continue;
    ASSERT_FALSE(tried.empty()) << "scan " << k;
    for (const auto& c : tried) EXPECT_FLOAT_EQ(c.grid, d.options.slow_grid) << "scan " << k;
    const OdometryStep& s = d.odometry.steps()[static_cast<std::size_t>(k)];
    EXPECT_TRUE(s.slow) << "scan " << k;
    EXPECT_EQ(s.grid, d.options.slow_grid) << "scan " << k;
  }
  EXPECT_GE(d.odometry.counters().slow, 6u);
  EXPECT_NEAR(d.odometry.steps().back().pose.head<2>().norm(), 0.0, 0.05);
}

TEST(ScanningOdometry, BusFillingTheViewTriggersTheFailureHandling) {
  // A static scene of weak returns and, from scan 4 on, a bus alongside moving with the car:
  // strong, dense and fixed in the vehicle frame, so it pulls the match to zero motion. The
  // motion prior must reject that, retry (bigger grids, then s halved) and fall back to constant
  // velocity if nothing passes, leaving the trajectory close to the truth.
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.f, 0.03f);
  const std::vector<Eigen::Vector2d> world = street();
  const double step = 2.5;  // 10 m/s at 4 Hz
  ScanningOdometryOptions options;
  options.keyframes.distance = 0;  // scan to scan: every step sees the bus in its target
  ScanningOdometry odometry(options, scanningMatcher());
  for (int k = 0; k < 9; ++k) {
    pcl::PointCloud<PointRadar>::Ptr cloud = observeWorld(world, step * k, rng, noise);
    if (k >= 4)  // the bus: 12 m x 2.5 m beside the car, densely filled and saturated
      for (double bx = -4; bx <= 8; bx += 0.125)
        for (double by = 2.5; by <= 5.0; by += 0.125) {
          PointRadar p(static_cast<float>(bx), static_cast<float>(by), 0.f, 1.0f);
          p.cov_xx = p.cov_yy = 0.01f;
          cloud->push_back(p);
        }
    odometry.addScan(ScanFrame{1000000 + 250000 * k, cloud});
  }
  const auto& c = odometry.counters();
  EXPECT_GE(c.retried + c.fallbacks, 1u) << "the bus steps must not pass at the nominal grid";
  for (std::size_t k = 5; k < odometry.steps().size(); ++k) {
    const OdometryStep& s = odometry.steps()[k];
    EXPECT_GT(s.motion.x(), 1.5) << "step " << k << " (" << toString(s.status) << ") accepted the bus's zero motion";
  }
  EXPECT_NEAR(odometry.steps().back().pose.x(), step * 8, 1.0);
  EXPECT_NEAR(odometry.steps().back().pose.y(), 0.0, 0.5);
}

TEST(ScanningOdometry, AScenePoorerForGoodCausesNoFallbackStorm) {
  // Two facades and poles, then from scan 8 on 1.5 times as many clutter returns that differ from scan to
  // scan (rain, open land): every match still finds the facades, but fits its target only a
  // fraction as well per point as before. The fit check must refuse the first of those (it looks
  // like an all-noise scan) and then learn the new level: a few fallbacks, then matches again.
  std::mt19937 rng(5);
  std::normal_distribution<float> noise(0.f, 0.03f);
  std::uniform_real_distribution<float> uniform(-55.f, 55.f);
  std::vector<Eigen::Vector2d> world;
  for (double x = -60; x <= 200; x += 0.5)
    if (std::fmod(x + 60, 17.0) < 13.0) {
      world.emplace_back(x, 9.0);
      world.emplace_back(x, -11.0 + 0.02 * x);
    }
  for (double x = -60; x <= 200; x += 7.0) world.emplace_back(x, 6.5 + std::fmod(x, 3.0));
  const double step = 2.0;
  const int scans = 40, change = 8;
  ScanningOdometryOptions options;
  ScanningOdometry odometry(options, scanningMatcher());
  for (int k = 0; k < scans; ++k) {
    pcl::PointCloud<PointRadar>::Ptr cloud = observeWorld(world, step * k, rng, noise);
    if (k >= change)
      for (std::size_t i = 0, n = 3 * cloud->size() / 2; i < n; ++i) {
        PointRadar p(uniform(rng), uniform(rng), 0.f, 0.45f);
        p.cov_xx = p.cov_yy = 0.01f;
        cloud->push_back(p);
      }
    odometry.addScan(ScanFrame{1000000 + 250000 * k, cloud});
  }
  const auto& steps = odometry.steps();
  ASSERT_EQ(steps.size(), static_cast<std::size_t>(scans));
  std::size_t failed_after_change = 0;
  for (int k = change; k < scans; ++k) failed_after_change += steps[k].status == StepStatus::Fallback;
  EXPECT_GE(odometry.counters().poor_fit, 1u) << "the first cluttered scan fits far worse than the clean ones";
  EXPECT_LE(failed_after_change, options.fit.history / 2 + 1) << "the fit check did not adapt to the poorer scene";
  for (int k = scans - 10; k < scans; ++k)
    EXPECT_EQ(steps[k].status, StepStatus::Matched) << "step " << k << " long after the change";

  EXPECT_NEAR(steps.back().pose.x(), step * (scans - 1), 1.0);
  EXPECT_NEAR(steps.back().pose.y(), 0.0, 0.5);
}

TEST(ScanningOdometry, KeepsNoPointerToTheCallersCloud) {
  // After addScan returns, the caller's cloud is the caller's alone: the odometry copies what it
  // keeps (the keyframe, the matcher's source), so the caller may reuse or change it at once, with
  // motion compensation or without, matched to keyframes or scan to scan.
  std::mt19937 rng(9);
  std::normal_distribution<float> noise(0.f, 0.03f);
  std::vector<Eigen::Vector2d> world;
  for (double x = -60; x <= 120; x += 0.5) {
    world.emplace_back(x, 9.0);
    if (std::fmod(x, 7.0) < 0.5) world.emplace_back(x, -8.0 + std::fmod(x, 2.0));
  }
  std::vector<pcl::PointCloud<PointRadar>> scans;
  for (int k = 0; k < 8; ++k) {
    pcl::PointCloud<PointRadar> cloud = *observeWorld(world, 2.0 * k, rng, noise);
    for (std::size_t i = 0; i < cloud.size(); ++i) cloud[i].time_offset = 0.25f * static_cast<float>(i % 400) / 400.f;
    scans.push_back(cloud);
  }
  for (const bool compensate : {true, false})
    for (const double keyframe_distance : {8.0, 0.0}) {
      ScanningOdometryOptions options;
      options.compensation.enabled = compensate;
      options.keyframes.distance = keyframe_distance;
      ScanningOdometry kept(options, scanningMatcher());
      ScanningOdometry reused(options, scanningMatcher());
      std::vector<pcl::PointCloud<PointRadar>::Ptr> kept_clouds;
      for (std::size_t k = 0; k < scans.size(); ++k) {
        kept_clouds.emplace_back(new pcl::PointCloud<PointRadar>(scans[k]));
        kept.addScan(ScanFrame{1000000 + 250000 * static_cast<std::int64_t>(k), kept_clouds.back()});
        pcl::PointCloud<PointRadar>::Ptr mine(new pcl::PointCloud<PointRadar>(scans[k]));
        reused.addScan(ScanFrame{1000000 + 250000 * static_cast<std::int64_t>(k), mine});
        EXPECT_EQ(mine.use_count(), 1) << "scan " << k << ": the odometry still holds the caller's cloud";
        for (auto& p : *mine) p.x += 100.f;  // the caller reuses its buffer
      }
      ASSERT_EQ(kept.steps().size(), reused.steps().size());
      for (std::size_t k = 0; k < kept.steps().size(); ++k)
        EXPECT_EQ(kept.steps()[k].pose, reused.steps()[k].pose)
            << "scan " << k << ", compensation " << compensate << ", keyframe distance " << keyframe_distance;
      EXPECT_NEAR(kept.steps().back().pose.x(), 14.0, 0.5);
    }
}

TEST(ScanningOdometry, EachCompensationRoundUsesTheVelocityThePreviousMatchFound) {
  // Scan to scan, each point carrying its time across the sweep; the speed steps from 8 to
  // 10.4 m/s at scan 5, so the constant-velocity guess is 2.4 m/s off there. The first round
  // compensates the source with the guess's velocity; the next compensates both the source and
  // the previous scan (the target) with the velocity the first match found. (The scans are seen
  // from one place each, so their time offsets only label the points: what is checked is which
  // velocity each round moves them with, not the motion found.)
  std::mt19937 rng(13);
  std::normal_distribution<float> noise(0.f, 0.03f);
  const std::vector<Eigen::Vector2d> world = street();
  ScanningOdometryOptions options;
  options.keyframes.distance = 0;
  auto matcher = recordingMatcher();
  matcher->keep_clouds = true;
  ScanningOdometry odometry(options, atNominal(matcher));
  const double dt = 0.25;
  std::vector<pcl::PointCloud<PointRadar>> raw;
  std::vector<std::size_t> first_match;  // index into matcher->matches of each scan's first align()
  double x0 = 0;
  for (int k = 0; k < 7; ++k) {
    x0 += k == 0 ? 0.0 : (k < 5 ? 2.0 : 2.6);
    pcl::PointCloud<PointRadar> cloud = *observeWorld(world, x0, rng, noise);
    for (std::size_t i = 0; i < cloud.size(); ++i)
      cloud[i].time_offset = 0.25f * static_cast<float>(i) / static_cast<float>(cloud.size());
    raw.push_back(cloud);
    first_match.push_back(matcher->matches.size());
    odometry.addScan(ScanFrame{1000000 + 250000 * static_cast<std::int64_t>(k),
                               pcl::make_shared<pcl::PointCloud<PointRadar>>(cloud)});
  }
  const int k = 5;
  const auto& steps = odometry.steps();
  ASSERT_EQ(steps[k].status, StepStatus::Matched);
  ASSERT_GE(steps[k].compensation_rounds, 2) << "a velocity 2.4 m/s off must call for a second round";
  ASSERT_GE(matcher->matches.size(), first_match[k] + 2);
  const auto& round0 = matcher->matches[first_match[k]];
  const auto& round1 = matcher->matches[first_match[k] + 1];
  auto expectSame = [](const pcl::PointCloud<PointRadar>& a, const pcl::PointCloud<PointRadar>& b, const char* what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    double worst = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
      worst = std::max({worst, std::abs(double(a[i].x) - b[i].x), std::abs(double(a[i].y) - b[i].y)});
    EXPECT_LT(worst, 1e-4) << what;
  };
  pcl::PointCloud<PointRadar> expected;
  compensateMotion(raw[k], velocityOf(steps[k - 1].motion, dt), expected);  // the constant-velocity guess
  expectSame(round0.source, expected, "round 0's source: the guess's velocity");
  const Eigen::Vector3d found = velocityOf(toPose2(round0.result), dt);
  EXPECT_GT(found.x(), 9.6) << "the first match must see the new speed";
  compensateMotion(raw[k], found, expected);
  expectSame(round1.source, expected, "round 1's source: the first match's velocity");
  compensateMotion(raw[k - 1], found, expected);
  expectSame(round1.target, expected, "round 1's target: the previous scan at the first match's velocity");
}

TEST(ScanningOdometry, JointCompensationMatchesTheSourceAsGivenWithTheStepsSweep) {
  // Each scan truly swept: a point at time offset τ is seen from where the vehicle is then (8 m/s
  // along the street). With CompensationMode::Joint every match after the second scan's start
  // hypotheses gets the scan as given (its time offsets kept), and the matcher places it with the
  // step: Δt and the previous scan's pose in the keyframe's frame. Afterwards the matcher is rigid.
  std::mt19937 rng(17);
  std::normal_distribution<float> noise(0.f, 0.03f);
  const std::vector<Eigen::Vector2d> world = street();
  ScanningOdometryOptions options;
  options.compensation.mode = CompensationMode::Joint;
  auto matcher = recordingMatcher();
  matcher->keep_clouds = true;
  ScanningOdometry odometry(options, atNominal(matcher));
  std::vector<pcl::PointCloud<PointRadar>> raw;
  std::vector<std::size_t> first_call;
  const double speed = 8.0, dt = 0.25;
  for (int k = 0; k < 12; ++k) {
    pcl::PointCloud<PointRadar> cloud;
    const double x0 = speed * dt * k;
    for (const auto& w : world) {
      const double az = std::atan2(w.y(), w.x() - x0);  // seen from the reference pose: its azimuth
      const double tau = dt * (az + kPi) / (2 * kPi);
      const double x = w.x() - (x0 + speed * tau), y = w.y();
      if (std::hypot(x, y) > 60) continue;
      PointRadar p(static_cast<float>(x) + noise(rng), static_cast<float>(y) + noise(rng), 0.f, 0.45f);
      p.cov_xx = p.cov_yy = 0.01f;
      p.time_offset = static_cast<float>(tau);
      cloud.push_back(p);
    }
    raw.push_back(cloud);
    first_call.push_back(matcher->calls.size());
    odometry.addScan(ScanFrame{1000000 + 250000 * static_cast<std::int64_t>(k),
                               pcl::make_shared<pcl::PointCloud<PointRadar>>(cloud)});
    EXPECT_FALSE(matcher->hasSourceSweep()) << "scan " << k << ": the matcher must be rigid between scans";
  }
  first_call.push_back(matcher->calls.size());
  const auto& steps = odometry.steps();
  Pose2 keyframe = Pose2::Zero();
  bool some_from_a_keyframe = false;
  for (std::size_t k = 1; k < steps.size(); ++k) {
    ASSERT_EQ(steps[k].status, StepStatus::Matched) << "step " << k;
    if (k >= 2) {
      const Pose2 previous = between(keyframe, steps[k - 1].pose);
      some_from_a_keyframe |= previous.head<2>().norm() > 1.0;
      for (std::size_t c = first_call[k]; c < first_call[k + 1]; ++c) {
        const auto& call = matcher->calls[c];
        ASSERT_TRUE(call.sweep) << "step " << k;
        EXPECT_DOUBLE_EQ(call.sweep_dt, dt) << "step " << k;
        EXPECT_LT((call.sweep_previous - previous).norm(), 1e-9) << "step " << k;
        const auto& source = matcher->matches[c].source;
        ASSERT_EQ(source.size(), raw[k].size());
        for (std::size_t i = 0; i < source.size(); ++i) {
          ASSERT_EQ(source[i].x, raw[k][i].x) << "step " << k << ": the source as given";
          ASSERT_EQ(source[i].time_offset, raw[k][i].time_offset) << "step " << k << ": its times kept";
        }
      }
    }
    if (steps[k].keyframe) keyframe = steps[k].pose;
  }
  EXPECT_TRUE(some_from_a_keyframe) << "the keyframes must be more than the previous scan for the test to say so";
  EXPECT_NEAR(steps.back().pose.x(), speed * dt * 11, 0.1);
  EXPECT_NEAR(steps.back().pose.y(), 0.0, 0.1);
}

TEST(ScanningOdometry, JointCompensationRefusesAMatcherThatCannotPlaceASweep) {
  ScanningOdometryOptions options;
  options.compensation.mode = CompensationMode::Joint;
  EXPECT_THROW(ScanningOdometry(options, scanningMatcher("pcl-ndt")), std::invalid_argument);
  EXPECT_NO_THROW(ScanningOdometry(options, scanningMatcher()));
  options.compensation.enabled = false;  // nothing to place: any matcher
  EXPECT_NO_THROW(ScanningOdometry(options, scanningMatcher("pcl-ndt")));
  EXPECT_EQ(parseEnum<CompensationMode>("joint"), CompensationMode::Joint);
  EXPECT_STREQ(toString(parseEnum<CompensationMode>("rounds")), "rounds");
  EXPECT_THROW(parseEnum<CompensationMode>("both"), std::invalid_argument);
}

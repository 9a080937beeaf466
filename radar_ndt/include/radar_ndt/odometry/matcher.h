#pragma once
// The scan matcher the odometries drive: any pcl::Registration<PointRadar, PointRadar>, behind a
// small adapter (MatcherAdapter) that knows the few things the pipelines change or judge at run
// time: the grid (retries enlarge it), the power shift (the scanning pipeline halves it) and the
// match's score. MatcherOptions hold every matcher setting, each in one place, with one default
// per radar kind (forScanning, forAutomotive); makeMatcher() builds the method they name from the
// registry of matchers (odometry/matcher_registry.h).

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>

#include <Eigen/Core>
#include <pcl/registration/registration.h>

#include "radar_ndt/fields.h"
#include "radar_ndt/point_types.h"
#include "radar_ndt/registration/weighted_ndt_2d.h"

namespace radar_ndt {

using RadarRegistration = pcl::Registration<PointRadar, PointRadar, float>;

namespace detail {
template <typename R, typename = void>
struct HasResolution : std::false_type {};
template <typename R>
struct HasResolution<R, std::void_t<decltype(std::declval<R&>().setResolution(1.f))>> : std::true_type {};
template <typename R, typename = void>
struct HasTransformationLikelihood : std::false_type {};
template <typename R>
struct HasTransformationLikelihood<R, std::void_t<decltype(std::declval<R&>().getTransformationLikelihood())>>
    : std::true_type {};
// PCL before 1.12 names the NDT score getTransformationProbability.
template <typename R, typename = void>
struct HasTransformationProbability : std::false_type {};
template <typename R>
struct HasTransformationProbability<R, std::void_t<decltype(std::declval<R&>().getTransformationProbability())>>
    : std::true_type {};
}  // namespace detail

/// What an attempt of the odometry sets on its matcher: the grid (NDT cell size g; ICP's maximum
/// correspondence distance) and the power shift s of eq. (1)-(2) (matchers with power weights).
struct MatchSettings {
  double grid = 0;
  float power_shift = 0;
};

/// A registration and what the odometry may change or read on it that pcl::Registration does not
/// say, decided once, from the static type it is built from (no casts at run time):
///  - WeightedNDT2D: grid = resolution, power shift, everything else from its result
///    (WeightedNDT2DResult: score, score per point, pose covariance);
///  - a matcher with setResolution (PCL's NDT): grid = resolution, score = its transformation
///    likelihood (when it has one);
///  - any other (PCL's ICP, a user's): grid = max correspondence distance, score = −fitness score.
/// Pass the concrete type's pointer: a WeightedNDT2D given as a plain RadarRegistration::Ptr is
/// driven as "any other". Empty (no registration): the odometry dead-reckons.
/// The adapter holds the nominal settings the odometry returns to after its retries, and the ones
/// the matcher holds now: apply() sets only what differs.
class MatcherAdapter {
 public:
  using WeightedNdt = WeightedNDT2D<PointRadar, PointRadar>;

  MatcherAdapter() = default;
  MatcherAdapter(std::nullptr_t) {}
  /// `registration` driven at `nominal`, which is set on it here.
  template <typename R, typename = std::enable_if_t<std::is_base_of_v<RadarRegistration, R>>>
  MatcherAdapter(std::shared_ptr<R> registration, const MatchSettings& nominal) : registration_(registration) {
    if (!registration) return;
    R* r = registration.get();
    if constexpr (std::is_base_of_v<WeightedNdt, R>) weighted_ndt_ = r;
    grid_is_resolution_ = detail::HasResolution<R>::value;
    if constexpr (detail::HasResolution<R>::value)
      set_grid_ = [r](double g) { r->setResolution(static_cast<float>(g)); };
    else
      set_grid_ = [r](double g) { r->setMaxCorrespondenceDistance(g); };
    if constexpr (std::is_base_of_v<WeightedNdt, R>)
      ;  // WeightedNDT2D reports through its result
    else if constexpr (detail::HasTransformationLikelihood<R>::value)
      score_ = [r] { return r->getTransformationLikelihood(); };
    else if constexpr (detail::HasTransformationProbability<R>::value)
      score_ = [r] { return r->getTransformationProbability(); };
    setNominal(nominal);
  }

  explicit operator bool() const { return static_cast<bool>(registration_); }
  RadarRegistration& registration() const { return *registration_; }
  const RadarRegistration::Ptr& registrationPtr() const { return registration_; }
  /// The WeightedNDT2D, or nullptr for another matcher.
  WeightedNdt* weightedNdt() const { return weighted_ndt_; }
  /// Whether the grid is an NDT resolution (WeightedNDT2D, PCL's NDT) rather than ICP's
  /// correspondence distance.
  bool gridIsResolution() const { return grid_is_resolution_; }
  /// Whether the matcher weighs points by their power (the power shift means something to it).
  bool hasPowerWeights() const { return weighted_ndt_ != nullptr; }

  /// The settings the odometry returns to; set on the matcher at once.
  void setNominal(const MatchSettings& nominal) {
    nominal_ = nominal;
    set_grid_(nominal.grid);
    if (weighted_ndt_) weighted_ndt_->setPowerShift(nominal.power_shift);
    current_ = nominal;
  }
  const MatchSettings& nominal() const { return nominal_; }
  /// What the matcher holds now (the power shift: 0 for a matcher without power weights).
  MatchSettings current() const { return {current_.grid, weighted_ndt_ ? current_.power_shift : 0.f}; }
  /// Sets `s` on the matcher, each setting only where it differs from what the matcher holds.
  void apply(const MatchSettings& s) {
    if (s.grid != current_.grid) set_grid_(current_.grid = s.grid);
    if (weighted_ndt_ && s.power_shift != current_.power_shift)
      weighted_ndt_->setPowerShift(current_.power_shift = s.power_shift);
  }
  /// How well the last align() fits, larger is better, comparable between aligns of the same
  /// source and target.
  double score() const {
    if (weighted_ndt_) return weighted_ndt_->getNdtScore();
    return score_ ? score_() : -registration_->getFitnessScore();
  }
  /// WeightedNDT2D only: the last align()'s NDT score per source point
  /// (WeightedNDT2DResult::scorePerPoint); NaN for other matchers.
  double fitPerPoint() const {
    return weighted_ndt_ ? weighted_ndt_->getResult().scorePerPoint() : std::numeric_limits<double>::quiet_NaN();
  }
  /// The last align()'s pose covariance as the matcher reports it; NaN for a matcher without one.
  Eigen::Matrix3d poseCovariance() const {
    return weighted_ndt_ ? weighted_ndt_->getResult().pose_covariance
                         : Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  }

 private:
  RadarRegistration::Ptr registration_;
  WeightedNdt* weighted_ndt_ = nullptr;
  bool grid_is_resolution_ = false;
  std::function<void(double)> set_grid_;
  std::function<double()> score_;
  MatchSettings nominal_, current_;
};

/// Every setting of the matchers, each in one place: the method (a name in the registry of
/// matchers), the grid and power shift every attempt starts from, and each method's own settings.
/// One default per radar kind: forScanning() and forAutomotive().
struct MatcherOptions {
  std::string method = "pw-ndt";
  double grid = 3.0;        ///< NDT cell size g (m); ICP: maximum correspondence distance
  float power_shift = 0.f;  ///< s of eq. (1)-(2), for matchers with power weights
  /// false: s shifts the cells' weights (eq. 1) only, the matching weights are p·exp(−½(σx + σy))
  /// (an ablation; the paper shifts both).
  bool shift_source_weights = true;
  /// WeightedNDT2D's (pw-ndt, rapp-ndt) other settings. Its grid, power shift and source shift are
  /// the three above: makeMatcher sets them, and validate() refuses them set here instead.
  /// Probabilistic cells (Hong & Lee 2017) include their points' own covariances, so one detection
  /// defines a usable Gaussian: sparse automotive submaps would lose most cells to WeightedNDT2D's
  /// default minimum of 3.
  WeightedNDT2DSettings weighted_ndt = defaultWeightedNdt();
  int weighted_ndt_max_iterations = 30;
  /// PCL's NDT as compared wherever it is (applyPclNdtSettings): Newton step 0.5, ε 1e-4, at
  /// most 50 iterations; PCL's ICP: at most 50 iterations, ε 1e-8, Euclidean fitness ε 1e-8.
  int icp_max_iterations = 50;
  double icp_transformation_epsilon = 1e-8;
  double icp_fitness_epsilon = 1e-8;

  static WeightedNDT2DSettings defaultWeightedNdt() {
    WeightedNDT2DSettings s;
    s.min_points_per_cell = 1;
    return s;
  }
  /// The scanning radars' defaults (the paper's Oxford values): g = 3.75 m, s = 0.333, and Biber's
  /// four overlapping grids (the 2x2-neighbour lookup leaves a grid-dependent bias on dense scans).
  static MatcherOptions forScanning();
  /// The automotive radars' defaults (the paper's nuScenes values): g = 3 m, no power shift.
  static MatcherOptions forAutomotive();
  /// The grid and power shift every attempt starts from.
  MatchSettings nominal() const { return {grid, power_shift}; }
  /// Throws std::invalid_argument naming the setting out of range, or a method the registry lacks.
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

/// The registered methods' names and what each is, "pw-ndt (…) | pcl-ndt (…) | …"
/// (matcher_registry.h; for the field table's help).
std::string matcherChoices();

template <typename Visit>
void MatcherOptions::fields(Visit&& visit) {
  using S = MatcherOptions;
  visit(&S::method, Field("method", "the matcher, by its registered name").cli("method").choices(&matcherChoices));
  visit(&S::grid,
        Field("grid", "NDT grid size g (pcl-icp: max correspondence distance)").unit("m").positive().cli("grid"));
  visit(&S::power_shift, Field("power_shift", "pw-ndt: power shift s of the weights max(p - s, 0); 0 turns it off")
                             .atLeast(0)
                             .below(1)
                             .cli("power-shift"));
  visit(&S::shift_source_weights,
        Field("shift_source_weights", "pw-ndt: the matching weights use the shift too (the paper)")
            .offSwitch("no-source-shift",
                       "pw-ndt: shift the cells' weights (eq. 1) only; the matching weights "
                       "are p·exp(-(σx+σy)/2) (ablation; the paper shifts both)"));
  visit(&S::weighted_ndt, Field("weighted_ndt", "pw-ndt's and rapp-ndt's other settings"));
  visit(&S::weighted_ndt_max_iterations,
        Field("weighted_ndt_max_iterations", "pw-ndt's and rapp-ndt's iterations per grid stage").atLeast(1));
  visit(&S::icp_max_iterations, Field("icp_max_iterations", "pcl-icp's iterations").atLeast(1));
  visit(&S::icp_transformation_epsilon,
        Field("icp_transformation_epsilon", "pcl-icp's transformation epsilon").atLeast(0));
  visit(&S::icp_fitness_epsilon, Field("icp_fitness_epsilon", "pcl-icp's Euclidean fitness epsilon").atLeast(0));
}

/// A new matcher for `options.method`, from the registry of matchers, at options.nominal(); an
/// empty adapter for a method that matches nothing (doppler).
MatcherAdapter makeMatcher(const MatcherOptions& options);

/// The settings pcl::NormalDistributionsTransform runs with wherever it is compared with ours
/// (any point type): resolution = grid, step 0.5, ε 1e-4, at most 50 iterations.
template <typename PclNdt>
void applyPclNdtSettings(PclNdt& ndt, double grid) {
  ndt.setResolution(static_cast<float>(grid));
  ndt.setStepSize(0.5);
  ndt.setTransformationEpsilon(1e-4);
  ndt.setMaximumIterations(50);
}

}  // namespace radar_ndt

#pragma once
// The scan matcher the odometries drive: any pcl::Registration<PointRadar, PointRadar>, behind a
// small adapter (MatcherAdapter) that knows the few things the pipelines change or judge at run
// time: the grid (retries enlarge it), the power shift (the scanning pipeline halves it) and the
// match's score. makeMatcher() builds ours, PCL's NDT or PCL's ICP with their settings
// (MatcherOptions); PCL's templates for PointRadar are compiled once, in src/odometry/matcher.cpp.

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>

#include <Eigen/Core>
#include <pcl/registration/registration.h>

#include "radar_ndt/point_types.h"
#include "radar_ndt/registration/weighted_ndt_2d.h"

namespace radar_ndt {

using RadarRegistration = pcl::Registration<PointRadar, PointRadar, float>;

enum class Method {
  PwNdt,    ///< WeightedNDT2D (the paper's weighted probabilistic NDT), one point per cell minimum
  PclNdt,   ///< pcl::NormalDistributionsTransform
  PclIcp,   ///< pcl::IterativeClosestPoint
  Doppler,  ///< no matching: Kellner's ego-velocity integration
  RappNdt,  ///< grid NDT with Doppler-agreement weights (Rapp et al. 2017, grid-based as in the paper)
};

/// "pw-ndt", "pcl-ndt", "pcl-icp", "doppler", "rapp-ndt"; throws std::invalid_argument otherwise.
Method parseMethod(const std::string& name);
const char* toString(Method method);

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

/// A registration and what the odometry may change or read on it that pcl::Registration does not
/// say, decided once, from the static type it is built from (no casts at run time):
///  - ours (WeightedNDT2D): grid = resolution, power shift, everything else from its result
///    (WeightedNDT2DResult: score, score per point, pose covariance);
///  - a matcher with setResolution (PCL's NDT): grid = resolution, score = its transformation
///    likelihood (when it has one);
///  - any other (PCL's ICP, a user's): grid = max correspondence distance, score = −fitness score.
/// Pass the concrete type's pointer: a WeightedNDT2D given as a plain RadarRegistration::Ptr is
/// driven as "any other". Empty (no registration): the odometry dead-reckons.
class MatcherAdapter {
 public:
  using Ours = WeightedNDT2D<PointRadar, PointRadar>;

  MatcherAdapter() = default;
  MatcherAdapter(std::nullptr_t) {}
  template <typename R, typename = std::enable_if_t<std::is_base_of_v<RadarRegistration, R>>>
  MatcherAdapter(std::shared_ptr<R> registration) : registration_(registration) {
    if (!registration) return;
    R* r = registration.get();
    if constexpr (std::is_base_of_v<Ours, R>) ours_ = r;
    grid_is_resolution_ = detail::HasResolution<R>::value;
    if constexpr (detail::HasResolution<R>::value)
      set_grid_ = [r](double g) { r->setResolution(static_cast<float>(g)); };
    else
      set_grid_ = [r](double g) { r->setMaxCorrespondenceDistance(g); };
    if constexpr (std::is_base_of_v<Ours, R>)
      ;  // ours reports through its result
    else if constexpr (detail::HasTransformationLikelihood<R>::value)
      score_ = [r] { return r->getTransformationLikelihood(); };
    else if constexpr (detail::HasTransformationProbability<R>::value)
      score_ = [r] { return r->getTransformationProbability(); };
  }

  explicit operator bool() const { return static_cast<bool>(registration_); }
  RadarRegistration& registration() const { return *registration_; }
  const RadarRegistration::Ptr& registrationPtr() const { return registration_; }
  /// Ours, or nullptr for another matcher.
  Ours* ours() const { return ours_; }
  /// Whether the grid is an NDT resolution (ours, PCL's NDT) rather than ICP's correspondence distance.
  bool gridIsResolution() const { return grid_is_resolution_; }

  /// The grid size: NDT cell size, or ICP's max correspondence distance (m).
  void setGrid(double grid) const { set_grid_(grid); }
  /// Sets the power shift s of eq. (1)-(2), in the cells and, when `shift_source` (the paper), in
  /// the matching weights; false (nothing changed) for a matcher without power weights.
  bool setPowerShift(float shift, bool shift_source = true) const {
    if (!ours_) return false;
    ours_->setPowerShift(shift);
    ours_->setShiftSourceWeights(shift_source);
    return true;
  }
  /// How well the last align() fits, larger is better, comparable between aligns of the same
  /// source and target.
  double score() const {
    if (ours_) return ours_->getNdtScore();
    return score_ ? score_() : -registration_->getFitnessScore();
  }
  /// Ours only: the last align()'s NDT score per source point (WeightedNDT2DResult::scorePerPoint);
  /// NaN for other matchers.
  double fitPerPoint() const {
    return ours_ ? ours_->getResult().scorePerPoint() : std::numeric_limits<double>::quiet_NaN();
  }
  /// The last align()'s pose covariance as the matcher reports it; NaN for a matcher without one.
  Eigen::Matrix3d poseCovariance() const {
    return ours_ ? ours_->getResult().pose_covariance
                 : Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  }

 private:
  RadarRegistration::Ptr registration_;
  Ours* ours_ = nullptr;
  bool grid_is_resolution_ = false;
  std::function<void(double)> set_grid_;
  std::function<double()> score_;
};

/// The settings each method is built with (the grid comes from the odometry's options).
struct MatcherOptions {
  Method method = Method::PwNdt;
  /// Ours (pw-ndt, rapp-ndt): the matcher's settings, except the grid and the power shift, which
  /// the odometry sets from its own options. Probabilistic cells (Hong & Lee 2017) include their
  /// points' own covariances, so one detection defines a usable Gaussian: sparse automotive
  /// submaps would lose most cells to WeightedNDT2D's default minimum of 3.
  WeightedNDT2DSettings ours = defaultOurs();
  int ours_max_iterations = 30;
  /// PCL's NDT as compared wherever it is (applyPclNdtSettings): Newton step 0.5, ε 1e-4, at
  /// most 50 iterations; PCL's ICP: at most 50 iterations, ε 1e-8, Euclidean fitness ε 1e-8.
  int icp_max_iterations = 50;
  double icp_transformation_epsilon = 1e-8;
  double icp_fitness_epsilon = 1e-8;

  static WeightedNDT2DSettings defaultOurs() {
    WeightedNDT2DSettings s;
    s.min_points_per_cell = 1;
    return s;
  }
  /// Throws std::invalid_argument naming the setting out of range.
  void validate() const;
};

/// A new matcher for `options.method` at grid size `grid` (NDT cell size; ICP: max correspondence
/// distance), or an empty adapter for Method::Doppler. The odometries own the grid: they set their
/// options' grid on the matcher they are given, whatever it was built with.
MatcherAdapter makeMatcher(const MatcherOptions& options, double grid = 3.0);
/// makeMatcher with the default settings of `method`.
MatcherAdapter makeMatcher(Method method, double grid = 3.0);

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

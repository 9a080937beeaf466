#include "radar_ndt/frontend/ego_velocity_3d.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace radar_ndt {

namespace {

/// The MSAC cost of v over all rows (squared residuals of the inliers, thr² for each outlier: ties
/// between equal counts go to the tighter fit) and the inlier count.
std::pair<double, std::size_t> msac(const std::vector<Eigen::Vector3d>& rows, const std::vector<double>& rhs,
                                    const Eigen::Vector3d& v, double thr) {
  double cost = 0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double e = std::abs(rows[i].dot(v) - rhs[i]);
    if (e <= thr) {
      cost += e * e;
      ++count;
    } else {
      cost += thr * thr;
    }
  }
  return {cost, count};
}

/// The squared Mahalanobis distance from a prediction's velocity under a covariance, factored once
/// for every velocity asked about (RANSAC's hypotheses); infinite when the covariance is singular.
class PriorDistance {
 public:
  PriorDistance(const EgoVelocityPrior& prior, const Eigen::Matrix3d& extra = Eigen::Matrix3d::Zero())
      : velocity_(prior.velocity), ldlt_(prior.covariance + extra) {
    usable_ = ldlt_.info() == Eigen::Success && ldlt_.rcond() > 1e-12;
  }
  double operator()(const Eigen::Vector3d& v) const {
    if (!usable_) return std::numeric_limits<double>::infinity();
    const Eigen::Vector3d d = v - velocity_;
    return d.dot(ldlt_.solve(d));
  }

 private:
  Eigen::Vector3d velocity_;
  Eigen::LDLT<Eigen::Matrix3d> ldlt_;
  bool usable_ = false;
};

/// RANSAC over minimal samples of three directions with the MSAC cost (deterministic: fixed seed,
/// own index draw); false when no sample had independent directions. With a prior, its velocity
/// is the first hypothesis and samples beyond its gate are passed over.
bool ransac(const std::vector<Eigen::Vector3d>& rows, const std::vector<double>& rhs, const EgoVelocity3DOptions& o,
            const EgoVelocityPrior* prior, Eigen::Vector3d* best_out) {
  const std::size_t n = rows.size();
  std::mt19937 rng(o.seed);
  Eigen::Vector3d best = Eigen::Vector3d::Zero();
  double best_cost = std::numeric_limits<double>::infinity();
  std::optional<PriorDistance> distance;
  if (prior) {
    best = prior->velocity;
    best_cost = msac(rows, rhs, best, o.inlier_threshold).first;
    distance.emplace(*prior);
  }
  for (int it = 0; it < o.max_iterations; ++it) {
    const std::size_t a = rng() % n, b = rng() % n, c = rng() % n;
    if (a == b || a == c || b == c) continue;
    Eigen::Matrix3d A;
    A << rows[a].transpose(), rows[b].transpose(), rows[c].transpose();
    // Near-coplanar directions leave one component of v free.
    if (std::abs(A.determinant()) < 1e-3) continue;
    const Eigen::Vector3d v = A.partialPivLu().solve(Eigen::Vector3d(rhs[a], rhs[b], rhs[c]));
    if (!v.allFinite() || v.norm() > 100.0) continue;
    if (distance && (*distance)(v) > prior->gate) continue;
    const double cost = msac(rows, rhs, v, o.inlier_threshold).first;
    if (cost < best_cost) {
      best_cost = cost;
      best = v;
    }
  }
  *best_out = best;
  return std::isfinite(best_cost);
}

/// Least squares on the inliers of v, twice (the refit may gain or lose border points): v, the
/// normal matrix and the inlier flags; the inlier count, 0 when the normal matrix is singular.
std::size_t refine(const std::vector<Eigen::Vector3d>& rows, const std::vector<double>& rhs, double thr,
                   Eigen::Vector3d& v, Eigen::Matrix3d& AtA, std::vector<char>& in) {
  const std::size_t n = rows.size();
  in.assign(n, 0);
  std::size_t m = 0;
  for (int round = 0; round < 2; ++round) {
    AtA.setZero();
    Eigen::Vector3d Atb = Eigen::Vector3d::Zero();
    m = 0;
    for (std::size_t i = 0; i < n; ++i) {
      in[i] = std::abs(rows[i].dot(v) - rhs[i]) <= thr;
      if (!in[i]) continue;
      AtA.noalias() += rows[i] * rows[i].transpose();
      Atb += rows[i] * rhs[i];
      ++m;
    }
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(AtA);
    if (m < 3 || ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-9)) return 0;
    v = ldlt.solve(Atb);
  }
  return m;
}

/// v from the rows (RANSAC, then least squares on its inliers), judged: `in` flags the inliers.
EgoVelocity3D fit(const std::vector<Eigen::Vector3d>& rows, const std::vector<double>& rhs,
                  const EgoVelocity3DOptions& o, const EgoVelocityPrior* prior, std::vector<char>& in) {
  EgoVelocity3D out;
  const std::size_t n = rows.size();
  out.points = n;
  in.assign(n, 0);
  if (n < std::max<std::size_t>(o.min_inliers, 3)) {
    out.why = std::to_string(n) + " usable detections, " + std::to_string(std::max<std::size_t>(o.min_inliers, 3)) +
              " needed";
    return out;
  }
  Eigen::Vector3d v;
  if (!ransac(rows, rhs, o, prior, &v)) {
    out.why = "no three detections in independent directions";
    return out;
  }
  Eigen::Matrix3d AtA;
  const std::size_t m = refine(rows, rhs, o.inlier_threshold, v, AtA, in);
  if (m == 0) {
    out.why = "the static detections' directions span a plane: one component of the velocity is unobserved";
    return out;
  }
  double r2 = 0;
  // The residuals at the final estimate, over the final inliers.
  for (std::size_t i = 0; i < n; ++i)
    if (in[i]) r2 += std::pow(rows[i].dot(v) - rhs[i], 2);
  out.velocity = v;
  out.inliers = m;
  out.residual_rms = std::sqrt(r2 / static_cast<double>(m));
  const double s2 = std::max(r2 / std::max(1.0, static_cast<double>(m) - 3.0), o.doppler_sigma * o.doppler_sigma);
  out.covariance = s2 * AtA.inverse();
  if (m < o.min_inliers || static_cast<double>(m) < o.min_inlier_ratio * static_cast<double>(n)) {
    out.why = std::to_string(m) + " of " + std::to_string(n) + " detections static: too few to trust";
    return out;
  }
  const double distance = prior ? PriorDistance(*prior, out.covariance)(v) : 0.0;
  if (prior && !(distance <= prior->gate)) {
    out.why = "the static consensus is " + std::to_string(distance) + " (chi-square) from the predicted velocity";
    return out;
  }
  out.valid = true;
  return out;
}

/// The rows the prior's velocity explains: within the inlier threshold plus three of the
/// prediction's own standard deviations along each row.
void priorInliers(const std::vector<Eigen::Vector3d>& rows, const std::vector<double>& rhs,
                  const EgoVelocityPrior& prior, double thr, std::vector<char>& in) {
  in.assign(rows.size(), 0);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double sigma = std::sqrt(std::max(0.0, rows[i].dot(prior.covariance * rows[i])));
    in[i] = std::abs(rows[i].dot(prior.velocity) - rhs[i]) <= thr + 3 * sigma;
  }
}

}  // namespace

void EgoVelocity3DOptions::validate() const {
  checkFields(*this, "EgoVelocity3DOptions");
}

EgoVelocity3D EgoVelocity3DEstimator::estimate(const std::vector<Eigen::Vector3d>& positions,
                                               const std::vector<double>& doppler, std::vector<bool>* inlier,
                                               const EgoVelocityPrior* prior) const {
  const EgoVelocity3DOptions& o = options_;
  if (inlier) inlier->assign(positions.size(), false);
  if (positions.size() != doppler.size()) {
    EgoVelocity3D out;
    out.why = "positions and Doppler differ in number";
    return out;
  }
  // One row a usable detection: v_r = −u · v.
  std::vector<Eigen::Vector3d> rows;
  std::vector<double> rhs;
  std::vector<std::size_t> index;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const double r = positions[i].norm();
    if (!positions[i].allFinite() || !std::isfinite(doppler[i]) || !(r > std::max(o.min_range, 1e-6))) continue;
    rows.push_back(-positions[i] / r);
    rhs.push_back(doppler[i]);
    index.push_back(i);
  }
  std::vector<char> in;
  const EgoVelocity3D out = fit(rows, rhs, o, prior, in);
  if (!inlier) return out;
  if (!out.valid && prior) priorInliers(rows, rhs, *prior, o.inlier_threshold, in);
  for (std::size_t i = 0; i < rows.size(); ++i) (*inlier)[index[i]] = in[i] != 0;
  return out;
}

}  // namespace radar_ndt

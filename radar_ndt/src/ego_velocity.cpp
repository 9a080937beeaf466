#include "radar_ndt/ego_velocity.h"

#include <cmath>
#include <limits>
#include <random>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace radar_ndt {

namespace {

/// One row of the linear model v_r = a · v: a = −[cos φ, sin φ, mx sin φ − my cos φ].
bool modelRow(const SensorMounting& m, double px, double py, Eigen::Vector3d& a) {
  const double dx = px - m.x, dy = py - m.y;
  const double r = std::hypot(dx, dy);
  if (!(r > 0.1)) return false;
  const double c = dx / r, s = dy / r;
  a << -c, -s, -(m.x * s - m.y * c);
  return true;
}

}  // namespace

double predictedDoppler(const SensorMounting& m, double px, double py, const Eigen::Vector3d& v) {
  Eigen::Vector3d a;
  return modelRow(m, px, py, a) ? a.dot(v) : 0.0;
}

EgoVelocity EgoVelocityEstimator::estimate(const pcl::PointCloud<PointRadar>& cloud, const std::vector<SensorMounting>& mountings,
                                           std::vector<bool>* inlier) const {
  EgoVelocity out;
  if (inlier) inlier->assign(cloud.size(), false);
  std::vector<Eigen::Vector3d> rows;
  std::vector<double> rhs;
  std::vector<std::size_t> index;  // row → point
  rows.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const PointRadar& p = cloud[i];
    if (p.sensor_id >= mountings.size() || !mountings[p.sensor_id].valid) continue;
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.doppler)) continue;
    Eigen::Vector3d a;
    if (!modelRow(mountings[p.sensor_id], p.x, p.y, a)) continue;
    rows.push_back(a);
    rhs.push_back(p.doppler);
    index.push_back(i);
  }
  const std::size_t n = rows.size();
  out.points = n;
  if (n < std::max<std::size_t>(3, options_.min_inliers)) return out;

  const double thr = options_.inlier_threshold;
  auto countInliers = [&](const Eigen::Vector3d& v, double* cost) {
    std::size_t c = 0;
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double e = std::abs(rows[i].dot(v) - rhs[i]);
      if (e <= thr) {
        ++c;
        sum += e * e;
      } else {
        sum += thr * thr;  // MSAC cost: ties between equal counts go to the tighter fit
      }
    }
    *cost = sum;
    return c;
  };

  // RANSAC: minimal samples of 3 detections; deterministic generator (fixed seed, own index draw).
  std::mt19937 rng(options_.seed);
  auto draw = [&](std::size_t bound) { return static_cast<std::size_t>(rng() % bound); };
  Eigen::Vector3d best = Eigen::Vector3d::Zero();
  double best_cost = std::numeric_limits<double>::infinity();
  std::size_t best_count = 0;
  for (int it = 0; it < options_.max_iterations; ++it) {
    const std::size_t i0 = draw(n), i1 = draw(n), i2 = draw(n);
    if (i0 == i1 || i0 == i2 || i1 == i2) continue;
    Eigen::Matrix3d A;
    A.row(0) = rows[i0].transpose();
    A.row(1) = rows[i1].transpose();
    A.row(2) = rows[i2].transpose();
    if (std::abs(A.determinant()) < 1e-3) continue;  // near-collinear directions: ω unobservable
    const Eigen::Vector3d v = A.partialPivLu().solve(Eigen::Vector3d(rhs[i0], rhs[i1], rhs[i2]));
    if (!v.allFinite() || v.head<2>().norm() > 100.0 || std::abs(v.z()) > 3.0) continue;  // not a car
    double cost;
    const std::size_t c = countInliers(v, &cost);
    if (cost < best_cost) {
      best_cost = cost;
      best_count = c;
      best = v;
    }
  }
  if (best_count < 3) return out;

  // Least squares on the inliers, twice (the refit may gain or lose border points).
  Eigen::Vector3d v = best;
  std::vector<char> in(n, 0);
  std::size_t m = 0;
  Eigen::Matrix3d AtA;
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
    if (m < 3) return out;
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(AtA);
    if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-9)) return out;
    v = ldlt.solve(Atb);
  }
  double rss = 0;
  std::size_t m_final = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!in[i]) continue;
    const double e = rows[i].dot(v) - rhs[i];
    rss += e * e;
    ++m_final;
  }
  out.velocity = v;
  out.inliers = m_final;
  out.residual_rms = std::sqrt(rss / static_cast<double>(m_final));
  // σ² from the residuals, floored at the ARS408's Doppler resolution (0.1 km/h ≈ 0.03 m/s) so a
  // lucky tight fit does not claim more than the sensor can give.
  const double sigma2 = std::max(rss / static_cast<double>(std::max<std::size_t>(m_final, 4) - 3), 0.03 * 0.03);
  out.covariance = sigma2 * AtA.inverse();
  out.valid = m_final >= options_.min_inliers &&
              static_cast<double>(m_final) >= options_.min_inlier_ratio * static_cast<double>(n) && out.covariance.allFinite();
  if (inlier)
    for (std::size_t i = 0; i < n; ++i) (*inlier)[index[i]] = in[i] != 0;
  return out;
}

}  // namespace radar_ndt

#include "radar_ndt/frontend/ego_velocity.h"

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

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

/// The ARS408's Doppler resolution (0.1 km/h ≈ 0.03 m/s): the smallest residual σ a fit may claim.
constexpr double kDopplerFloor = 0.03;
/// vy's variance under the nonholonomic model when no lateral σ is set: (1 m/s)², i.e. unknown.
constexpr double kFreeLateral = 1.0;
/// ω's variance when the radars cannot see it (the forward-speed fit): (1 rad/s)², i.e. unknown.
constexpr double kFreeYawRate = 1.0;
/// Radars closer than this (m) sit at one place: they see one velocity.
constexpr double kOnePlace = 0.2;

/// The MSAC cost of x over all rows: squared residuals of the inliers, thr² for each outlier (ties
/// between equal counts go to the tighter fit); and the inlier count.
template <int D>
std::pair<double, std::size_t> msacCost(const std::vector<Eigen::Matrix<double, D, 1>>& rows,
                                        const std::vector<double>& rhs, const Eigen::Matrix<double, D, 1>& x,
                                        double thr) {
  std::size_t c = 0;
  double sum = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double e = std::abs(rows[i].dot(x) - rhs[i]);
    if (e <= thr) {
      ++c;
      sum += e * e;
    } else {
      sum += thr * thr;
    }
  }
  return std::make_pair(sum, c);
}

/// RANSAC over minimal samples of D rows with the MSAC cost: the best plausible x (`full` maps it
/// to (vx, vy, ω): a car's speed and yaw rate) and its inlier count (0: none found).
template <int D, typename Full>
std::size_t ransacDoppler(const std::vector<Eigen::Matrix<double, D, 1>>& rows, const std::vector<double>& rhs,
                          const EgoVelocityOptions& o, Full full, Eigen::Matrix<double, D, 1>* best_out) {
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;
  const std::size_t n = rows.size();
  // Deterministic generator (fixed seed, own index draw).
  std::mt19937 rng(o.seed);
  auto draw = [&](std::size_t bound) { return static_cast<std::size_t>(rng() % bound); };
  Vec best = Vec::Zero();
  double best_cost = std::numeric_limits<double>::infinity();
  std::size_t best_count = 0;
  for (int it = 0; it < o.max_iterations; ++it) {
    std::size_t pick[D];
    bool distinct = true;
    for (int k = 0; k < D; ++k) {
      pick[k] = draw(n);
      for (int j = 0; j < k; ++j) distinct = distinct && pick[j] != pick[k];
    }
    if (!distinct) continue;
    Mat A;
    Vec b;
    for (int k = 0; k < D; ++k) {
      A.row(k) = rows[pick[k]].transpose();
      b(k) = rhs[pick[k]];
    }
    if (std::abs(A.determinant()) < 1e-3) continue;  // near-collinear directions: ω unobservable
    const Vec x = A.partialPivLu().solve(b);
    const Eigen::Vector3d v = full(x);
    if (!v.allFinite() || v.head<2>().norm() > 100.0 || std::abs(v.z()) > 3.0) continue;  // not a car
    const auto [c, count] = msacCost<D>(rows, rhs, x, o.inlier_threshold);
    if (c < best_cost) {
      best_cost = c;
      best_count = count;
      best = x;
    }
  }
  *best_out = best;
  return best_count;
}

/// Least squares on the inliers of x, twice (the refit may gain or lose border points); with
/// prior_index ≥ 0 also observing x[prior_index] = 0 with σ prior_sigma. False for too few inliers
/// or a degenerate normal matrix; else x, the normal matrix (prior included) and the inlier flags.
template <int D>
bool refineDoppler(const std::vector<Eigen::Matrix<double, D, 1>>& rows, const std::vector<double>& rhs, double thr,
                   int prior_index, double prior_sigma, Eigen::Matrix<double, D, 1>& x,
                   Eigen::Matrix<double, D, D>& AtA, std::vector<char>& in) {
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;
  const std::size_t n = rows.size();
  in.assign(n, 0);
  for (int round = 0; round < 2; ++round) {
    AtA.setZero();
    Vec Atb = Vec::Zero();
    std::size_t m = 0;
    double r2 = 0;  // the inliers' residual sum of squares at the current x
    for (std::size_t i = 0; i < n; ++i) {
      const double e = rows[i].dot(x) - rhs[i];
      in[i] = std::abs(e) <= thr;
      if (!in[i]) continue;
      AtA.noalias() += rows[i] * rows[i].transpose();
      Atb += rows[i] * rhs[i];
      r2 += e * e;
      ++m;
    }
    if (m < static_cast<std::size_t>(D)) return false;
    if (prior_index >= 0) {
      // The zero-mean prior on x[prior_index] as one more observation, weighted against the
      // detections by their residual variance at the current estimate.
      const double s2 = std::max(r2 / std::max(1.0, static_cast<double>(m) - D), kDopplerFloor * kDopplerFloor);
      AtA(prior_index, prior_index) += s2 / (prior_sigma * prior_sigma);
    }
    const Eigen::LDLT<Mat> ldlt(AtA);
    if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-9)) return false;
    x = ldlt.solve(Atb);
  }
  return true;
}

/// RANSAC (minimal samples of D detections, MSAC cost) and least squares on the inliers for the
/// model v_r = a · x with x of dimension D; `full` maps x to (vx, vy, ω) for the plausibility
/// check. With prior_index ≥ 0 the least squares also observes x[prior_index] = 0 with σ
/// prior_sigma (RANSAC does not). Returns false when no consensus or a degenerate inlier set;
/// else x, the normal matrix (prior included), the inlier flags and their residual sum of squares.
template <int D, typename Full>
bool fitDoppler(const std::vector<Eigen::Matrix<double, D, 1>>& rows, const std::vector<double>& rhs,
                const EgoVelocityOptions& o, Full full, int prior_index, double prior_sigma,
                Eigen::Matrix<double, D, 1>* x_out, Eigen::Matrix<double, D, D>* ata_out, std::vector<char>* in_out,
                double* rss_out) {
  Eigen::Matrix<double, D, 1> x;
  if (ransacDoppler<D>(rows, rhs, o, full, &x) < static_cast<std::size_t>(D)) return false;
  Eigen::Matrix<double, D, D> AtA;
  std::vector<char>& in = *in_out;
  if (!refineDoppler<D>(rows, rhs, o.inlier_threshold, prior_index, prior_sigma, x, AtA, in)) return false;
  double rss = 0;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (in[i]) {
      const double e = rows[i].dot(x) - rhs[i];
      rss += e * e;
    }
  *x_out = x;
  *ata_out = AtA;
  *rss_out = rss;
  return true;
}

/// The Doppler model's rows (and right-hand sides) of the cloud's usable detections, the point
/// each comes from, and the detections per sensor.
void dopplerRows(const pcl::PointCloud<PointRadar>& cloud, const std::vector<SensorMounting>& mountings,
                 std::vector<Eigen::Vector3d>& rows, std::vector<double>& rhs, std::vector<std::size_t>& index,
                 std::vector<std::size_t>& per_sensor) {
  per_sensor.assign(mountings.size(), 0);
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
    ++per_sensor[p.sensor_id];
  }
}

/// The full model needs radars at two places at least, each with enough detections to fix its own
/// velocity: one place sees only its own velocity.
bool needsNonholonomic(const EgoVelocityOptions& o, const std::vector<SensorMounting>& mountings,
                       const std::vector<std::size_t>& per_sensor) {
  if (o.model != EgoVelocityModel::Auto) return o.model == EgoVelocityModel::Nonholonomic;
  auto enough = [&](std::size_t k) { return per_sensor[k] >= o.min_inliers; };
  double spread = 0;
  for (std::size_t a = 0; a < mountings.size(); ++a)
    for (std::size_t b = a + 1; b < mountings.size(); ++b)
      if (enough(a) && enough(b))
        spread = std::max(spread, std::hypot(mountings[a].x - mountings[b].x, mountings[a].y - mountings[b].y));
  return spread < kOnePlace;
}

/// Under vy = 0 a radar at (mx, my) sees the forward speed vx − ω my alone when mx = 0: the
/// Kellner 2013 rows' ω column, mx sin φ − my cos φ, is then the vx column times −my. True (and
/// `my` the radars' mean lateral offset) when every radar with enough detections (or, with none,
/// every one with any) sits at one place within kOnePlace of the rear axle's line (x = 0).
bool yawRateUnseen(const EgoVelocityOptions& o, const std::vector<SensorMounting>& mountings,
                   const std::vector<std::size_t>& per_sensor, double& my) {
  std::size_t most = 0;
  for (std::size_t n : per_sensor) most = std::max(most, n);
  const std::size_t needed = most >= o.min_inliers ? o.min_inliers : 1;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0;
  std::size_t count = 0;
  for (std::size_t k = 0; k < mountings.size(); ++k) {
    if (per_sensor[k] < needed) continue;
    if (!(std::abs(mountings[k].x) < kOnePlace)) return false;
    lo = std::min(lo, mountings[k].y);
    hi = std::max(hi, mountings[k].y);
    sum += mountings[k].y;
    ++count;
  }
  if (count == 0 || hi - lo >= kOnePlace) return false;
  my = sum / static_cast<double>(count);
  return true;
}

/// vy = 0: the rows keep the vx and ω columns. The velocity and its unscaled covariance.
bool fitNonholonomic(const std::vector<Eigen::Vector3d>& rows, const std::vector<double>& rhs,
                     const EgoVelocityOptions& o, EgoVelocity& out, std::vector<char>& in, double& rss) {
  std::vector<Eigen::Vector2d> rows2;
  rows2.reserve(rows.size());
  for (const auto& a : rows) rows2.emplace_back(a.x(), a.z());
  Eigen::Vector2d x;
  Eigen::Matrix2d AtA;
  if (!fitDoppler<2>(
          rows2, rhs, o, [](const Eigen::Vector2d& y) { return Eigen::Vector3d(y.x(), 0.0, y.y()); }, -1, 0.0, &x, &AtA,
          &in, &rss))
    return false;
  out.velocity = Eigen::Vector3d(x.x(), 0.0, x.y());
  const Eigen::Matrix2d C = AtA.inverse();
  out.covariance.setZero();
  out.covariance(0, 0) = C(0, 0);
  out.covariance(0, 2) = out.covariance(2, 0) = C(0, 1);
  out.covariance(2, 2) = C(1, 1);
  return true;
}

/// vy = 0 and the radars on the rear axle's line (yawRateUnseen): the forward speed u = vx − ω my
/// alone, the rows' vx column. ω is left to the match: reported 0 with variance kFreeYawRate, and vx
/// = u + ω my correlated with it. The velocity and its unscaled covariance (vx's part from u).
bool fitForwardSpeed(const std::vector<Eigen::Vector3d>& rows, const std::vector<double>& rhs,
                     const EgoVelocityOptions& o, EgoVelocity& out, std::vector<char>& in, double& rss) {
  std::vector<Eigen::Matrix<double, 1, 1>> rows1;
  rows1.reserve(rows.size());
  for (const auto& a : rows) rows1.emplace_back(a.x());
  Eigen::Matrix<double, 1, 1> x;
  Eigen::Matrix<double, 1, 1> AtA;
  if (!fitDoppler<1>(
          rows1, rhs, o, [](const Eigen::Matrix<double, 1, 1>& y) { return Eigen::Vector3d(y(0), 0.0, 0.0); }, -1, 0.0,
          &x, &AtA, &in, &rss))
    return false;
  out.velocity = Eigen::Vector3d(x(0), 0.0, 0.0);
  out.covariance.setZero();
  out.covariance(0, 0) = 1.0 / AtA(0, 0);
  return true;
}

/// (vx, vy, ω), vy with its prior when lateral_sigma > 0. The velocity and its unscaled covariance.
bool fitFull(const std::vector<Eigen::Vector3d>& rows, const std::vector<double>& rhs, const EgoVelocityOptions& o,
             EgoVelocity& out, std::vector<char>& in, double& rss) {
  Eigen::Vector3d x;
  Eigen::Matrix3d AtA;
  const bool prior = o.lateral_sigma > 0;
  if (!fitDoppler<3>(
          rows, rhs, o, [](const Eigen::Vector3d& y) { return y; }, prior ? 1 : -1, o.lateral_sigma, &x, &AtA, &in,
          &rss))
    return false;
  out.velocity = x;
  out.covariance = AtA.inverse();
  return true;
}

}  // namespace

double predictedDoppler(const SensorMounting& m, double px, double py, const Eigen::Vector3d& v) {
  Eigen::Vector3d a;
  return modelRow(m, px, py, a) ? a.dot(v) : 0.0;
}

void EgoVelocityOptions::validate() const {
  checkFields(*this, "EgoVelocityOptions");
}

EgoVelocity EgoVelocityEstimator::estimate(const pcl::PointCloud<PointRadar>& cloud,
                                           const std::vector<SensorMounting>& mountings,
                                           std::vector<bool>* inlier) const {
  EgoVelocity out;
  if (inlier) inlier->assign(cloud.size(), false);
  std::vector<Eigen::Vector3d> rows;
  std::vector<double> rhs;
  std::vector<std::size_t> index;  // row → point
  std::vector<std::size_t> per_sensor;
  dopplerRows(cloud, mountings, rows, rhs, index, per_sensor);
  const std::size_t n = rows.size();
  out.points = n;
  const bool nonholonomic = needsNonholonomic(options_, mountings, per_sensor);
  out.nonholonomic = nonholonomic;
  double my = 0;
  out.forward_only = nonholonomic && yawRateUnseen(options_, mountings, per_sensor, my);
  const std::size_t dims = out.forward_only ? 1 : nonholonomic ? 2 : 3;
  if (n < std::max(dims, options_.min_inliers)) return out;

  std::vector<char> in;
  double rss = 0;
  const bool fitted = out.forward_only ? fitForwardSpeed(rows, rhs, options_, out, in, rss)
                      : nonholonomic   ? fitNonholonomic(rows, rhs, options_, out, in, rss)
                                       : fitFull(rows, rhs, options_, out, in, rss);
  if (!fitted) return out;
  std::size_t m_final = 0;
  for (std::size_t i = 0; i < n; ++i) m_final += in[i] != 0;
  out.inliers = m_final;
  out.residual_rms = std::sqrt(rss / static_cast<double>(m_final));
  // σ² from the residuals, floored at the ARS408's Doppler resolution (0.1 km/h ≈ 0.03 m/s) so a
  // lucky tight fit does not claim more than the sensor can give.
  const double sigma2 =
      std::max(rss / static_cast<double>(std::max(m_final, dims + 1) - dims), kDopplerFloor * kDopplerFloor);
  out.covariance *= sigma2;
  if (nonholonomic)
    out.covariance(1, 1) = options_.lateral_sigma > 0 ? options_.lateral_sigma * options_.lateral_sigma : kFreeLateral;
  if (out.forward_only) {
    out.covariance(0, 0) += my * my * kFreeYawRate;
    out.covariance(0, 2) = out.covariance(2, 0) = my * kFreeYawRate;
    out.covariance(2, 2) = kFreeYawRate;
  }
  out.valid = m_final >= options_.min_inliers &&
              static_cast<double>(m_final) >= options_.min_inlier_ratio * static_cast<double>(n) &&
              out.covariance.allFinite();
  if (inlier)
    for (std::size_t i = 0; i < n; ++i) (*inlier)[index[i]] = in[i] != 0;
  return out;
}

}  // namespace radar_ndt

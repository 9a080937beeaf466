#include "motion_noise.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/LU>

namespace radar_ndt {
namespace apps {

namespace {
Pose2 error(const Pose2& estimate, const Pose2& truth) {
  Pose2 e = estimate - truth;
  e.z() = normalizeAngle(e.z());
  return e;
}
bool reported(const Eigen::Matrix3d& c) {
  return c.allFinite() && c.determinant() > 0;
}
}  // namespace

std::vector<MotionNoiseSample> motionNoiseSamples(const AutomotiveRunResult& run) {
  std::vector<MotionNoiseSample> out;
  const std::size_t n = std::min(run.steps.size(), run.ground_truth.size());
  for (std::size_t k = 1; k < n; ++k) {
    const OdometryStep& s = run.steps[k];
    const OdometryStep& p = run.steps[k - 1];
    if (s.status == StepStatus::First || s.status == StepStatus::Skipped || s.status == StepStatus::Bridged) continue;
    if (p.status == StepStatus::Skipped || !s.velocity_valid) continue;
    MotionNoiseSample m;
    m.dt = 1e-6 * static_cast<double>(s.timestamp_us - p.timestamp_us);
    m.truth = between(toPose2(run.ground_truth.poses[k - 1]), toPose2(run.ground_truth.poses[k]));
    if (!(m.dt > 0) || !m.truth.allFinite()) continue;
    m.doppler = s.prior_motion;
    m.doppler_covariance = s.prior_covariance;
    m.matched = s.status == StepStatus::Matched || s.status == StepStatus::Retried;
    m.match = s.match_motion;
    m.match_covariance = s.match_covariance;
    out.push_back(m);
  }
  return out;
}

MotionFusionOptions MotionNoiseCalibration::applyTo(MotionFusionOptions o, MatchCalibration which) const {
  if (doppler_samples > 0) {
    o.doppler_sigma_x = doppler_sigma_x;
    o.doppler_sigma_y = doppler_sigma_y;
    o.doppler_sigma_yaw = doppler_sigma_yaw;
  }
  if (reported_covariances > 0)
    (which == MatchCalibration::Rapp ? o.rapp_covariance_scale : o.match_covariance_scale) = match_covariance_scale;
  if (match_samples > 0 && which == MatchCalibration::PclIcp) {
    o.icp_sigma_x = match_sigma_x;
    o.icp_sigma_y = match_sigma_y;
    o.icp_sigma_yaw = match_sigma_yaw;
  } else if (match_samples > 0) {
    o.match_sigma_x = match_sigma_x;
    o.match_sigma_y = match_sigma_y;
    o.match_sigma_yaw = match_sigma_yaw;
  }
  return o;
}

MotionNoiseCalibration calibrateMotionNoise(const std::vector<MotionNoiseSample>& samples) {
  if (samples.empty()) throw std::invalid_argument("calibrateMotionNoise: no samples");
  MotionNoiseCalibration c;
  Eigen::Vector3d doppler = Eigen::Vector3d::Zero(), match = Eigen::Vector3d::Zero();
  double nees = 0;
  for (const auto& s : samples) {
    const Pose2 e = error(s.doppler, s.truth);
    // Per axis, the squared error the fit covariance does not explain, per second² of motion.
    for (int i = 0; i < 3; ++i) doppler[i] += (e[i] * e[i] - s.doppler_covariance(i, i)) / (s.dt * s.dt);
    ++c.doppler_samples;
    if (!s.matched) continue;
    const Pose2 em = error(s.match, s.truth);
    match += em.cwiseProduct(em);
    ++c.match_samples;
    if (reported(s.match_covariance)) {
      nees += em.dot(s.match_covariance.inverse() * em);
      ++c.reported_covariances;
    }
  }
  // A fit covariance that already explains an axis leaves a tiny noise, not a negative one.
  doppler = (doppler / static_cast<double>(c.doppler_samples)).cwiseMax(1e-12);
  c.doppler_sigma_x = std::sqrt(doppler.x());
  c.doppler_sigma_y = std::sqrt(doppler.y());
  c.doppler_sigma_yaw = std::sqrt(doppler.z());
  if (c.match_samples > 0) {
    match /= static_cast<double>(c.match_samples);
    c.match_sigma_x = std::sqrt(match.x());
    c.match_sigma_y = std::sqrt(match.y());
    c.match_sigma_yaw = std::sqrt(match.z());
  }
  if (c.reported_covariances > 0) c.match_covariance_scale = nees / static_cast<double>(c.reported_covariances) / 3.0;
  return c;
}

MotionNees motionNees(const std::vector<MotionNoiseSample>& samples, const MotionFusionOptions& options,
                      MatchCalibration which) {
  const MotionFusion fusion(options);
  MotionNees r;
  double d = 0, m = 0;
  for (const auto& s : samples) {
    const Pose2 e = error(s.doppler, s.truth);
    d += e.dot(fusion.dopplerCovariance(s.doppler_covariance, s.dt).inverse() * e);
    ++r.doppler_samples;
    if (!s.matched) continue;
    const Pose2 em = error(s.match, s.truth);
    const Eigen::Matrix3d C = fusion.matchCovariance(&s.match_covariance, which);  // NaN or degenerate: the σ's
    m += em.dot(C.inverse() * em);
    ++r.match_samples;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  r.doppler = r.doppler_samples ? d / static_cast<double>(r.doppler_samples) : nan;
  r.match = r.match_samples ? m / static_cast<double>(r.match_samples) : nan;
  return r;
}

MatchInformation matchInformation(const std::vector<MotionNoiseSample>& samples) {
  MatchInformation r;
  Eigen::Vector3d dd = Eigen::Vector3d::Zero(), mm = Eigen::Vector3d::Zero(), dm = Eigen::Vector3d::Zero();
  for (const auto& s : samples) {
    if (!s.matched) continue;
    const Pose2 ed = error(s.doppler, s.truth), em = error(s.match, s.truth);
    dd += ed.cwiseProduct(ed);
    mm += em.cwiseProduct(em);
    dm += ed.cwiseProduct(em);
    ++r.samples;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double n = static_cast<double>(r.samples);
  for (int i = 0; i < 3; ++i) {
    MatchInformationAxis& a = r.axis[i];
    if (r.samples < 2) {
      a = {nan, nan, nan, nan, nan};
      continue;
    }
    a.doppler_rms = std::sqrt(dd[i] / n);
    a.match_rms = std::sqrt(mm[i] / n);
    a.correlation = dm[i] / std::sqrt(dd[i] * mm[i]);
    // Σ (e_d + w (e_m − e_d))² is least at w* = −Σ e_d (e_m − e_d) / Σ (e_m − e_d)².
    const double diff2 = mm[i] - 2 * dm[i] + dd[i];
    a.oracle_weight = diff2 > 0 ? -(dm[i] - dd[i]) / diff2 : 0.0;
    const double w = a.oracle_weight;
    a.oracle_rms = std::sqrt(std::max(0.0, (dd[i] + 2 * w * (dm[i] - dd[i]) + w * w * diff2) / n));
  }
  return r;
}

}  // namespace apps
}  // namespace radar_ndt

#include "radar_ndt/odometry/radar_inertial_odometry.h"

#include <array>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <tuple>

#include "radar_ndt/odometry/imu_velocity.h"
#include "radar_ndt/registration/detail/point_fields.h"
#include "radar_ndt/registration/weighted_ndt_3d.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/se3.h"

namespace radar_ndt {

namespace {

using Cloud = pcl::PointCloud<PointRadar4D>;

/// The detections with a finite position and Doppler within [min_range, max_range].
Cloud withinRange(const Cloud& scan, double min_range, double max_range) {
  Cloud out;
  out.reserve(scan.size());
  for (const PointRadar4D& p : scan) {
    const double r = std::sqrt(double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z);
    if (std::isfinite(r) && std::isfinite(p.doppler) && r >= min_range && r <= max_range) out.push_back(p);
  }
  return out;
}

/// The detections whose Doppler the static world explains (all of them when the scan has no
/// valid ego-velocity and no prediction flagged them), moved into the body frame.
Cloud::Ptr staticBodyCloud(const Cloud& scan, const std::vector<bool>& inlier, bool use_inliers,
                           const Eigen::Isometry3d& radar_to_body) {
  Cloud kept;
  kept.reserve(scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (!use_inliers || inlier[i]) kept.push_back(scan[i]);
  return Cloud::Ptr(new Cloud(transformRadar4D(kept, radar_to_body)));
}

}  // namespace

void deskewBody(Cloud& body, const Eigen::Vector3d& velocity, const Eigen::Vector3d& omega) {
  for (PointRadar4D& p : body) {
    const double t = p.time_offset;
    if (t == 0.0 || !std::isfinite(t)) continue;
    const Eigen::Matrix3d R = expSO3(omega * t);
    const Eigen::Vector3d q = R * Eigen::Vector3d(p.x, p.y, p.z) + velocity * t + 0.5 * t * t * omega.cross(velocity);
    p.x = static_cast<float>(q.x());
    p.y = static_cast<float>(q.y());
    p.z = static_cast<float>(q.z());
    detail::rotateCovariance3D(p, R);
    p.time_offset = 0.f;
  }
}

namespace {

/// The match held to the prior's roll and pitch (a 4D radar's elevation is coarse; gravity holds
/// them). With the match's information Λ = C⁻¹ about it (C the matcher's covariance in
/// δ = (v, ω)), the most likely (v, ω_z) with ω_x, ω_y fixed at the prior's is
/// δ₄ = δ₄ᵐ + Λ₄₄⁻¹ Λ₄ᵣ δᵣᵐ (δᵐ the match relative to the prior), with covariance Λ₄₄⁻¹. Returns
/// the pose; `cov4` gets that covariance (6x6, the roll and pitch rows and columns zero).
Eigen::Isometry3d withPriorTilt(const Eigen::Isometry3d& prior, const Eigen::Isometry3d& measured, const Matrix6d& C,
                                Matrix6d* cov4) {
  Vector6d d;
  d.head<3>() = measured.translation() - prior.translation();
  d.tail<3>() = logSO3(measured.linear() * prior.linear().transpose());
  const std::array<int, 4> k = {0, 1, 2, 5};
  const Matrix6d L = C.inverse();
  Eigen::Matrix4d Lkk;
  Eigen::Matrix<double, 4, 2> Lkr;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) Lkk(i, j) = L(k[i], k[j]);
    Lkr(i, 0) = L(k[i], 3);
    Lkr(i, 1) = L(k[i], 4);
  }
  const Eigen::Matrix4d Ckk = Lkk.inverse();
  const Eigen::Vector4d dk = Eigen::Vector4d(d(0), d(1), d(2), d(5)) + Ckk * (Lkr * d.segment<2>(3));
  cov4->setZero();
  d.setZero();
  for (int i = 0; i < 4; ++i) {
    d(k[i]) = dk(i);
    for (int j = 0; j < 4; ++j) (*cov4)(k[i], k[j]) = Ckk(i, j);
  }
  return retractSE3(prior, d);
}

/// A usable covariance: finite, symmetric positive definite.
bool usable(const Matrix6d& C) {
  if (!C.allFinite()) return false;
  const Eigen::LLT<Matrix6d> llt(C);
  return llt.info() == Eigen::Success;
}

}  // namespace

/// What the prior says of the motion from the last scan to this one.
struct RadarInertialOdometry::Motion {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< the prior pose at the scan
  Eigen::Vector3d specific_force = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< body, bias removed
  bool has_imu = false;
};

void RadarInertialOptions::validate() const {
  checkFields(*this, "RadarInertialOptions");
  if (min_range >= max_range) throw std::invalid_argument("RadarInertialOptions: min_range must be below max_range");
  findMatcher3D(method);
}

RadarInertialOdometry::RadarInertialOdometry(const RadarInertialOptions& o, const Eigen::Isometry3d& radar_to_body)
    : options_(o), radar_to_body_(radar_to_body), ego_(o.ego_velocity), filter_(o.filter), map_(o.map) {
  options_.validate();
  entry_ = &findMatcher3D(options_.method);
  matcher_ = entry_->make(options_.matchers);
  match_scale_ = options_.match_covariance_scale;
}

RadarInertialOdometry::~RadarInertialOdometry() = default;

void RadarInertialOdometry::addImu(const ImuSample& in) {
  if (!options_.use_imu) return;
  ImuSample s = in;
  s.t += options_.imu_time_offset;
  const double last = !imu_.empty() ? imu_.back().t : (filter_.initialized() ? last_imu_.t : -INFINITY);
  if (!std::isfinite(s.t) || !s.gyro.allFinite() || !s.accel.allFinite() || s.t <= last) {
    ++dropped_imu_;
    return;
  }
  imu_.push_back(s);
}

std::vector<std::string> RadarInertialOdometry::problems() const {
  std::vector<std::string> out = problems_;
  if (dropped_imu_)
    out.push_back(std::to_string(dropped_imu_) + " IMU messages not finite or not later than the last: dropped");
  return out;
}

RadarInertialOdometry::Motion RadarInertialOdometry::priorMotion(double stamp, const Eigen::Vector3d& velocity,
                                                                 const Eigen::Matrix3d& velocity_covariance) {
  Motion m;
  const double interval = stamp - last_stamp_;
  if (!options_.use_imu) {
    const Eigen::Quaterniond q0(pose_.linear());
    m.pose.linear() = pose_.linear() * expSO3(rotation_rate_ * interval);
    const Eigen::Quaterniond q1(m.pose.linear());
    const Eigen::Vector3d v = 0.5 * (last_velocity_ + velocity);
    m.pose.translation() = pose_.translation() + q0.slerp(0.5, q1).toRotationMatrix() * v * interval;
    m.angular_velocity = rotation_rate_;
    return m;
  }
  // The IMU carried to the scan's time; the velocity linear between the last scan's and this one's.
  Eigen::Vector3d force_sum = Eigen::Vector3d::Zero();
  double force_time = 0;
  auto advance = [&](const ImuSample& b) {
    const double u = interval > 0 ? std::clamp((0.5 * (last_imu_.t + b.t) - last_stamp_) / interval, 0.0, 1.0) : 1.0;
    filter_.predict(last_imu_, b, (1 - u) * last_velocity_ + u * velocity, velocity_covariance, interval);
    force_sum += 0.5 * (last_imu_.accel + b.accel) * (b.t - last_imu_.t);
    force_time += b.t - last_imu_.t;
    last_imu_ = b;
  };
  std::size_t used = 0;
  for (; used < imu_.size() && imu_[used].t <= stamp; ++used) advance(imu_[used]);
  imu_.erase(imu_.begin(), imu_.begin() + static_cast<std::ptrdiff_t>(used));
  if (last_imu_.t < stamp) {
    ImuSample held = last_imu_;  // the last reading held to the scan's time
    held.t = stamp;
    advance(held);
  }
  m.has_imu = force_time > 0;
  m.specific_force = m.has_imu ? Eigen::Vector3d(force_sum / force_time) : last_imu_.accel;
  m.angular_velocity = last_imu_.gyro - filter_.gyroBias();
  m.pose = filter_.pose();
  return m;
}

void RadarInertialOdometry::match(const Cloud::Ptr& source, OdometryStep3D& step) {
  if (map_.empty() || source->size() < options_.min_points) {
    step.why = map_.empty() ? "no local map yet" : "too few static detections to match";
    return;
  }
  if (target_version_ != map_version_) {  // the map is not empty here: at least one keyframe added
    matcher_->setInputTarget(map_.cloud());
    target_version_ = map_version_;
  }
  matcher_->setInputSource(source);
  Cloud aligned;
  const auto t0 = std::chrono::steady_clock::now();
  matcher_->align(aligned, step.pose.matrix().cast<float>());
  step.match_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  step.iterations = entry_->iterations(*matcher_);
  const Pose3 measured = toPose3(matcher_->getFinalTransformation());
  if (!matcher_->hasConverged() || !allFinite(measured)) {
    step.why = "the matcher did not converge";
    return;
  }
  // The match's covariance: the matcher's own where it gives one (WeightedNDT3D: points taken as
  // independent, so optimistic), else the floors; times a factor adapted to the innovations
  // (below), plus the floors.
  const double st = options_.match_sigma_translation, sr = options_.match_sigma_rotation_deg * kPi / 180;
  Matrix6d floor = Matrix6d::Zero();
  floor.diagonal() << st * st, st * st, st * st, sr * sr, sr * sr, sr * sr;
  Matrix6d base = floor;
  if (const auto* ndt = dynamic_cast<const WeightedNDT3D<PointRadar4D, PointRadar4D>*>(matcher_.get()))
    if (usable(ndt->getPoseCovariance())) base = ndt->getPoseCovariance();
  if (!options_.use_imu) {
    step.pose = measured;
    step.covariance = match_scale_ * base + floor;
    step.matched = true;
    return;
  }
  Eigen::Isometry3d fused_from = measured;
  Matrix6d cov = base;
  std::array<bool, 6> axes = {true, true, true, true, true, true};
  if (!options_.match_roll_pitch) {
    fused_from = withPriorTilt(step.pose, measured, base, &cov);
    floor(3, 3) = floor(4, 4) = 1.0;  // rad²: no information on roll and pitch (nor used)
    axes[3] = axes[4] = false;
  }
  const double dof = options_.match_roll_pitch ? 6 : 4;
  cov = match_scale_ * cov + floor;
  double distance = 0;
  step.matched = filter_.updatePose(fused_from, cov, axes, &distance);
  // The factor follows the innovations: a match farther from the prior than its covariance and
  // the prior's say (squared Mahalanobis distance above its degrees of freedom) grows it, a
  // nearer one shrinks it (an adaptive measurement noise, as Mehra 1972), in small steps.
  if (std::isfinite(distance)) {
    const double step_log = std::clamp(std::log(std::max(distance, 1e-9) / dof), -1.0, 1.0);
    match_scale_ = std::clamp(match_scale_ * std::exp(options_.match_scale_rate * step_log), 1e-3, 1e9);
  }
  if (!step.matched) step.why = "the match was refused: " + std::to_string(distance) + " (chi-square) from the prior";
  step.pose = filter_.pose();
}

bool RadarInertialOdometry::ready(double stamp, OdometryStep3D& step) {
  if (started_ && !(stamp > last_stamp_)) {
    step.skipped = true;
    step.why = "a scan not later than the last one: skipped";
    return false;
  }
  if (!options_.use_imu || filter_.initialized()) return true;
  // The still start needs the IMU's first initial_seconds; scans before then give no pose.
  if (imu_.empty() || imu_.back().t - imu_.front().t < options_.filter.initial_seconds) {
    step.skipped = true;
    step.why = "waiting for the IMU's first " + std::to_string(options_.filter.initial_seconds) + " s";
    return false;
  }
  filter_.initialize(imu_, problems_);
  last_imu_ = imu_.front();
  last_stamp_ = last_imu_.t;
  if (filter_.stillStart()) {  // standing at the IMU's first message: the prediction starts there
    predicting_ = true;
    accepted_stamp_ = last_imu_.t;
    accepted_covariance_.setZero();
  }
  return true;
}

OdometryStep3D RadarInertialOdometry::addScan(double stamp, const Cloud& scan) {
  return addScans(stamp, {RadarScan4D{&scan, radar_to_body_, 0}});
}

bool RadarInertialOdometry::velocityPrediction(double stamp, Eigen::Vector3d& velocity,
                                               Eigen::Matrix3d& covariance) const {
  if (!predicting_) return false;
  double sigma;  // how fast the prediction grows uncertain
  if (options_.use_imu) {
    if (!options_.velocity_prior) return false;
    velocity = predictBodyVelocity(filter_.pose().linear(), last_velocity_, last_imu_, imu_.begin(), imu_.end(), stamp,
                                   filter_.gyroBias(), filter_.accelBias(), options_.filter.gravity);
    sigma = options_.velocity_prior_sigma;
  } else {
    if (!options_.velocity_prior_radar_only) return false;
    // The world's velocity held: the body's turns with the body (a constant-velocity model).
    velocity = expSO3(-rotation_rate_ * (stamp - last_stamp_)) * last_velocity_;
    sigma = options_.velocity_prior_radar_only_sigma;
  }
  covariance =
      predictedVelocityCovariance(accepted_covariance_, stamp - accepted_stamp_, options_.velocity_prior_floor, sigma);
  return velocity.allFinite() && covariance.allFinite();
}

Cloud::Ptr RadarInertialOdometry::frontEnd(const std::vector<RadarScan4D>& scans, OdometryStep3D& step,
                                           std::vector<std::pair<const RadarScan4D*, EgoVelocity3D>>& egos,
                                           const std::pair<Eigen::Vector3d, Eigen::Matrix3d>* predicted,
                                           const Eigen::Vector3d& omega) {
  Cloud::Ptr source;
  for (const RadarScan4D& s : scans) {
    const Cloud in_range = withinRange(*s.scan, options_.min_range, options_.max_range);
    step.points += in_range.size();
    std::vector<bool> inlier;
    EgoVelocityPrior prior;
    if (predicted) {  // the body's predicted velocity at the radar, in its axes
      const Eigen::Matrix3d Rt = s.radar_to_body.linear().transpose();
      prior.velocity = Rt * (predicted->first + omega.cross(s.radar_to_body.translation()));
      prior.covariance = Rt * predicted->second * Rt.transpose();
    }
    const EgoVelocity3D ego = ego_.estimate(in_range, &inlier, predicted ? &prior : nullptr);
    const Cloud::Ptr body = staticBodyCloud(in_range, inlier, ego.valid || predicted, s.radar_to_body);
    if (!source)
      source = body;
    else
      *source += *body;
    if (ego.valid) egos.emplace_back(&s, ego);
  }
  step.static_points = source->size();
  return source;
}

std::pair<Eigen::Vector3d, Eigen::Matrix3d> RadarInertialOdometry::stepVelocity(
    double stamp, const std::vector<std::pair<const RadarScan4D*, EgoVelocity3D>>& egos,
    const std::pair<Eigen::Vector3d, Eigen::Matrix3d>* predicted, const Eigen::Vector3d& omega) {
  if (egos.empty()) return predicted ? *predicted : std::make_pair(last_velocity_, Eigen::Matrix3d::Identity().eval());
  std::vector<std::pair<Eigen::Vector3d, Eigen::Matrix3d>> body;
  for (const auto& [s, ego] : egos)
    body.emplace_back(bodyVelocity(s->radar_to_body, ego.velocity, omega),
                      bodyVelocityCovariance(s->radar_to_body, ego.covariance));
  const auto fused = fuseBodyVelocities(body);
  accepted_stamp_ = stamp;
  accepted_covariance_ = fused.second;
  return fused;
}

OdometryStep3D RadarInertialOdometry::addScans(double stamp, const std::vector<RadarScan4D>& scans) {
  if (scans.empty()) throw std::invalid_argument("RadarInertialOdometry::addScans: no scan");
  OdometryStep3D step;
  step.stamp = stamp;
  const bool go = ready(stamp, step);
  const Eigen::Vector3d omega_guess =
      options_.use_imu ? Eigen::Vector3d((imu_.empty() ? last_imu_ : imu_.back()).gyro - filter_.gyroBias())
                       : rotation_rate_;
  std::pair<Eigen::Vector3d, Eigen::Matrix3d> predicted;
  const bool has_prediction = go && velocityPrediction(stamp, predicted.first, predicted.second);
  std::vector<std::pair<const RadarScan4D*, EgoVelocity3D>> egos;  // the valid ones
  const Cloud::Ptr source = frontEnd(scans, step, egos, has_prediction ? &predicted : nullptr, omega_guess);
  step.velocity_valid = !egos.empty();
  if (!go) return step;
  auto [velocity, velocity_cov] = stepVelocity(stamp, egos, has_prediction ? &predicted : nullptr, omega_guess);
  const bool valid = !egos.empty();
  // Standing still: the Doppler velocity within its noise of zero (and, radar only, no turn since
  // the last scan; with an IMU the gyro turns the prior whatever the scan says). The rig is taken
  // as not moving (a zero-velocity update, as hand-held inertial navigation makes at each step):
  // the velocity's noise is not integrated and the scan is not matched.
  step.still = valid && velocity.dot(velocity_cov.ldlt().solve(velocity)) < options_.still_velocity_chi2 &&
               (options_.use_imu || rotation_rate_.norm() < options_.still_rate);
  if (step.still) velocity.setZero();
  step.velocity = velocity;
  if (options_.deskew) deskewBody(*source, velocity, omega_guess);
  if (!started_) {
    if (!predicting_) {  // the first velocity, taken or held, starts the prediction
      predicting_ = true;
      accepted_stamp_ = stamp;
      accepted_covariance_ = velocity_cov;
    }
    if (options_.use_imu) {
      // The IMU's messages up to the scan carry the attitude to it; the odometry frame's origin
      // is the body at its first scan.
      last_velocity_ = velocity;
      priorMotion(stamp, velocity, velocity_cov);
      filter_.setPose(Eigen::Isometry3d(filter_.pose().linear()));
    }
    step.pose = options_.use_imu ? filter_.pose() : pose_;
    started_ = true;
  } else {
    const double dt = stamp - last_stamp_;
    const Motion prior = priorMotion(stamp, velocity, velocity_cov);
    // Gravity is read against the Doppler's acceleration; the IMU's own prediction would read back
    // the attitude it was integrated with.
    if (options_.use_imu && dt > 0 && (valid || !has_prediction))
      filter_.updateGravity(prior.specific_force,
                            (velocity - last_velocity_) / dt + prior.angular_velocity.cross(velocity),
                            (velocity_cov + last_velocity_covariance_) / (dt * dt));
    step.pose = options_.use_imu ? filter_.pose() : prior.pose;
    if (!(step.still && last_still_)) {
      match(source, step);
      step.fallback = !step.matched;
    }
    if (!options_.use_imu && dt > 0) rotation_rate_ = logSO3(pose_.linear().transpose() * step.pose.linear()) / dt;
  }
  if (options_.use_imu) step.covariance = filter_.poseCovariance();
  remember(step, velocity_cov, *source, scans.front().radar);
  return step;
}

void RadarInertialOdometry::remember(const OdometryStep3D& step, const Eigen::Matrix3d& velocity_covariance,
                                     const Cloud& source, std::uint16_t radar) {
  pose_ = step.pose;
  last_velocity_ = step.velocity;
  last_velocity_covariance_ = velocity_covariance;
  last_still_ = step.still;
  last_stamp_ = step.stamp;
  // A scan without a Doppler velocity has no confirmed static world (its detections are what a
  // prediction or nothing picked): it is matched but never joins the map.
  if (step.velocity_valid && map_.wantsKeyframe(step.pose, radar) && !source.empty()) {
    map_.add(source, step.pose, radar);
    ++map_version_;
  }
}

}  // namespace radar_ndt

#include "radar_ndt/pipeline/inertial_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>

#include "radar_ndt/frontend/ego_velocity_3d.h"
#include "radar_ndt/odometry/local_map_3d.h"
#include "radar_ndt/odometry/matcher_registry_3d.h"

namespace radar_ndt {

std::vector<std::string> inertialMethods() {
  std::vector<std::string> out = matcher3DNames();
  out.push_back("doppler-imu");
  return out;
}

bool isInertialMethod(const std::string& method) {
  const std::vector<std::string> all = inertialMethods();
  return std::find(all.begin(), all.end(), method) != all.end();
}

std::string inertialMethodChoices() {
  std::string out;
  for (const std::string& m : inertialMethods()) out += (out.empty() ? "" : " | ") + m;
  return out;
}

void InertialRunOptions::validate() const {
  checkFields(*this, "InertialRunOptions");
  if (!isInertialMethod(matcher.method))
    throw std::invalid_argument("matcher.method: no 6-DoF method '" + matcher.method + "' (" + inertialMethodChoices() +
                                ")");
  if (matcher.method == "doppler-imu" && !imu)
    throw std::invalid_argument("matcher.method doppler-imu integrates the IMU: it needs imu (--imu)");
  if (doppler_imu.radar_latency != 0)
    throw std::invalid_argument("doppler_imu.radar_latency: the run's radar_latency (--radar-latency) sets it");
  RadarInertialOptions o = odometry;
  if (matcher.method != "doppler-imu") o.method = matcher.method;
  o.validate();
  doppler_imu.validate();
}

InertialRunOptions inertialRunDefaults(const SensorDescription& d, const std::string& radar) {
  InertialRunOptions o;
  for (std::size_t i = 0; i < d.radars.size(); ++i) {
    const RadarDescription& r = d.radars[i];
    if (!r.fields.spherical) continue;
    const SphericalSigmas& a = *r.fields.spherical;
    const SphericalAccuracy accuracy{a.range, a.azimuth_deg, a.elevation_deg};
    if (r.name == radar)
      o.accuracy = accuracy;
    else
      o.radar_accuracy[static_cast<std::uint16_t>(i)] = accuracy;
  }
  return o;
}

pcl::PointCloud<PointRadar4D> toRadar4D(const pcl::PointCloud<PointRadar>& points, const SphericalAccuracy& accuracy) {
  pcl::PointCloud<PointRadar4D> scan;
  scan.reserve(points.size());
  for (const PointRadar& p : points) {
    PointRadar4D q(p.x, p.y, p.z, p.power);
    q.doppler = p.doppler;
    q.rcs = p.rcs;
    q.sensor_id = p.sensor_id;
    q.time_offset = p.time_offset;  // a driver's per-point time: the odometry de-skews by it
    scan.push_back(q);
  }
  setPointCovariances(scan, Eigen::Matrix3d::Identity(), accuracy);
  return scan;
}

std::vector<std::vector<RadarSweepData>> sweepsByTime(std::vector<RadarSweepData> sweeps, bool merge) {
  std::stable_sort(sweeps.begin(), sweeps.end(), [](const RadarSweepData& a, const RadarSweepData& b) {
    return a.timestamp_us != b.timestamp_us ? a.timestamp_us < b.timestamp_us : a.sensor_id < b.sensor_id;
  });
  std::vector<std::vector<RadarSweepData>> groups;
  for (RadarSweepData& sweep : sweeps) {
    if (groups.empty() || (!merge && groups.back().front().timestamp_us != sweep.timestamp_us)) groups.emplace_back();
    groups.back().push_back(std::move(sweep));
  }
  return groups;
}

namespace {

/// The odometry's options as the run's say: its method and whether the IMU is fused.
RadarInertialOptions odometryOptions(const InertialRunOptions& o) {
  RadarInertialOptions out = o.odometry;
  out.method = o.matcher.method;
  out.use_imu = o.imu;
  return out;
}

/// What each step's match starts from, for the summaries.
std::string priorOf(const InertialRunOptions& o) {
  if (o.matcher.method == "doppler-imu") return "none (gyro and Doppler velocity integrated, no match)";
  return o.imu ? "inertial filter (gyro, Doppler velocity, gravity)" : "last turn rate and Doppler velocity";
}

/// The gyro's last reading at or before `t` (the first one before it; zero without an IMU): what a
/// live run holds when the scan arrives.
Eigen::Vector3d gyroAt(const std::vector<ImuSample>& imu, double t) {
  const auto it = std::upper_bound(imu.begin(), imu.end(), t, [](double v, const ImuSample& s) { return v < s.t; });
  if (it == imu.begin()) return imu.empty() ? Eigen::Vector3d::Zero() : imu.front().gyro;
  return std::prev(it)->gyro;
}

/// The sweeps of cycle k of `cycles`, every radar's, as `sweepsByTime` groups them: one group for
/// the cycle when `merge`, else one a recorded time (time order, the groups' sweeps in radar order);
/// none when the cycle is unreadable (said in `r`). `radars` collects the radars met.
std::vector<std::vector<RadarSweepData>> loadSweeps(const RadarCycleSource& cycles, std::size_t k, bool merge,
                                                    InertialRunResult& r, std::set<std::uint16_t>& radars) {
  std::vector<std::string> problems;
  RadarCycle cycle;
  try {
    cycle = cycles.load(k, &problems);
  } catch (const std::exception& e) {
    problems.push_back(e.what());
  }
  for (const std::string& p : problems) r.problems.push_back("scan " + std::to_string(k) + ": " + p);
  if (cycle.sweeps.empty()) {
    ++r.unreadable;
    return {};
  }
  r.radar = cycles.referenceChannel();
  for (const RadarSweepData& sweep : cycle.sweeps) radars.insert(sweep.sensor_id);
  return sweepsByTime(std::move(cycle.sweeps), merge);
}

/// The group's detections in the body frame, each radar's through its mounting, with its accuracy.
pcl::PointCloud<PointRadar4D> bodyDetections(const std::vector<RadarSweepData>& sweeps, const InertialRunOptions& o) {
  pcl::PointCloud<PointRadar4D> out;
  for (const RadarSweepData& s : sweeps)
    out += transformRadar4D(toRadar4D(s.points, o.accuracyOf(s.sensor_id)), s.sensor_to_vehicle);
  return out;
}

/// The doppler-imu baseline over the whole recording: each scan's body velocity, then the IMU.
void runBaseline(const RadarCycleSource& cycles, const std::vector<ImuSample>& imu, const InertialRunOptions& o,
                 const std::function<void(std::size_t, std::size_t)>& progress, const InertialStepCallback& on_step,
                 InertialRunResult& r) {
  std::map<double, std::pair<std::size_t, pcl::PointCloud<PointRadar4D>>> body;  // stamp -> (k, scan)
  const EgoVelocity3DEstimator estimator(o.odometry.ego_velocity);
  std::vector<BodyVelocitySample> velocities;
  std::set<std::uint16_t> radars;
  std::size_t n = cycles.size();
  if (o.max_cycles) n = std::min(n, o.max_cycles);
  for (std::size_t k = 0; k < n; ++k) {
    for (const std::vector<RadarSweepData>& group : loadSweeps(cycles, k, o.merge_sweeps, r, radars)) {
      const double t = static_cast<double>(group.back().timestamp_us) * 1e-6 - o.radar_latency;
      std::vector<std::pair<Eigen::Vector3d, Eigen::Matrix3d>> valid;  // the radars' body velocities
      BodyVelocitySample sample{t, Eigen::Vector3d::Zero(), false};
      for (const RadarSweepData& sweep : group) {
        const EgoVelocity3D e = estimator.estimate(sweep.points);
        sample.velocity = bodyVelocity(sweep.sensor_to_vehicle, e.velocity, gyroAt(imu, t));
        if (e.valid) valid.emplace_back(sample.velocity, bodyVelocityCovariance(sweep.sensor_to_vehicle, e.covariance));
      }
      sample.valid = !valid.empty();
      if (sample.valid) std::tie(sample.velocity, sample.covariance) = fuseBodyVelocities(valid);
      velocities.push_back(sample);
      ++r.scans;
      if (on_step) body[t] = {k, bodyDetections(group, o)};
    }
    if (progress) progress(k + 1, n);
  }
  if (velocities.empty()) throw std::invalid_argument(r.sequence + ": no readable scan");
  r.radars = radars.size();
  DopplerImuResult d = runDopplerImu(imu, velocities, o.doppler_imu);
  r.estimate = d.trajectory;
  r.problems.insert(r.problems.end(), d.problems.begin(), d.problems.end());
  for (std::size_t i = 0; i < r.estimate.size(); ++i) {
    OdometryStep3D step;
    step.stamp = r.estimate.stamps[i];
    step.pose = r.estimate.poses[i];
    r.steps.push_back(step);
    const auto it = body.find(step.stamp);
    if (on_step && it != body.end()) on_step(it->second.first, step, it->second.second);
  }
}

/// The ground truth at the estimate's stamps (the scans' measurement times, as the truth's).
Trajectory truthAtEstimate(const Trajectory& truth, const Trajectory& estimate) {
  Trajectory out;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    Eigen::Isometry3d T;
    if (truth.poseAt(estimate.stamps[i], &T)) {
      out.stamps.push_back(estimate.stamps[i]);
      out.poses.push_back(T);
    }
  }
  return out;
}

/// Refuses IMU messages that share no time with the scans (another clock: a stamp rule that mixes
/// header stamps and receive times), naming both spans.
void checkClocks(const RadarCycleSource& cycles, const std::vector<ImuSample>& imu) {
  if (imu.empty() || cycles.size() == 0) return;
  const double first = static_cast<double>(cycles.timestamp(0)) * 1e-6;
  const double last = static_cast<double>(cycles.timestamp(cycles.size() - 1)) * 1e-6;
  if (imu.back().t >= first && imu.front().t <= last) return;
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "%s: the IMU's stamps (%.3f to %.3f s) share no time with the radar's (%.3f to %.3f s): two "
                "clocks (the description's stamps: receive puts both on the recorder's)",
                cycles.sceneName().c_str(), imu.front().t, imu.back().t, first, last);
  throw std::invalid_argument(buf);
}

}  // namespace

InertialStream::InertialStream(const InertialRunOptions& options, const Eigen::Isometry3d& radar_to_body)
    : options_((options.validate(), options)), odometry_(odometryOptions(options_), radar_to_body) {
  if (options_.matcher.method == "doppler-imu")
    throw std::invalid_argument("doppler-imu smooths the whole run: runInertialOdometry, not a stream");
}

void InertialStream::addImu(const ImuSample& sample) {
  if (options_.imu) odometry_.addImu(sample);
}

OdometryStep3D InertialStream::addScan(double stamp, const pcl::PointCloud<PointRadar>& points) {
  return odometry_.addScan(stamp - options_.radar_latency, toRadar4D(points, options_.accuracy));
}

OdometryStep3D InertialStream::addScans(double stamp, const std::vector<RadarSweepData>& sweeps) {
  std::vector<pcl::PointCloud<PointRadar4D>> clouds;
  clouds.reserve(sweeps.size());
  std::vector<RadarScan4D> scans;
  std::int64_t latest = 0;
  for (const RadarSweepData& s : sweeps) latest = std::max(latest, s.timestamp_us);
  for (const RadarSweepData& s : sweeps) {
    clouds.push_back(toRadar4D(s.points, options_.accuracyOf(s.sensor_id)));
    // A sweep before the step's time (merge_sweeps): its detections' offsets say how long before.
    if (s.timestamp_us != latest)
      for (PointRadar4D& p : clouds.back()) p.time_offset += static_cast<float>(1e-6 * double(s.timestamp_us - latest));
    scans.push_back({&clouds.back(), s.sensor_to_vehicle, s.sensor_id});
  }
  return odometry_.addScans(stamp - options_.radar_latency, scans);
}

InertialRunResult runInertialOdometry(const RadarCycleSource& cycles, const std::vector<ImuSample>& imu,
                                      const InertialRunOptions& o,
                                      const std::function<void(std::size_t, std::size_t)>& progress,
                                      const InertialStepCallback& on_step) {
  o.validate();
  if (o.imu && imu.empty())
    throw std::invalid_argument(cycles.sceneName() + ": imu asked for, but the recording has no IMU messages");
  if (o.imu) checkClocks(cycles, imu);
  const auto t0 = std::chrono::steady_clock::now();
  InertialRunResult r;
  r.sequence = cycles.sceneName();
  r.method = o.matcher.method;
  r.imu = o.imu;
  r.period_s = cycles.periodSeconds();
  r.prior = priorOf(o);
  if (o.matcher.method == "doppler-imu") {
    runBaseline(cycles, imu, o, progress, on_step, r);
  } else {
    std::unique_ptr<InertialStream> stream;
    std::set<std::uint16_t> radars;
    std::size_t next_imu = 0;
    std::size_t n = cycles.size();
    if (o.max_cycles) n = std::min(n, o.max_cycles);
    for (std::size_t k = 0; k < n; ++k) {
      for (const std::vector<RadarSweepData>& group : loadSweeps(cycles, k, o.merge_sweeps, r, radars)) {
        if (!stream) stream = std::make_unique<InertialStream>(o, group.front().sensor_to_vehicle);
        const double stamp = static_cast<double>(group.back().timestamp_us) * 1e-6;  // a group's latest
        for (; next_imu < imu.size() && imu[next_imu].t <= stamp - o.radar_latency; ++next_imu)
          stream->addImu(imu[next_imu]);
        const OdometryStep3D step = stream->addScans(stamp, group);
        ++r.scans;
        r.steps.push_back(step);
        if (!step.skipped) {
          r.estimate.stamps.push_back(step.stamp);
          r.estimate.poses.push_back(step.pose);
          if (on_step) on_step(k, step, bodyDetections(group, o));
        }
      }
      if (progress) progress(k + 1, n);
    }
    if (!stream) throw std::invalid_argument(r.sequence + ": no readable scan");
    r.radars = radars.size();
    const std::vector<std::string> p = stream->odometry().problems();
    r.problems.insert(r.problems.end(), p.begin(), p.end());
  }
  for (const OdometryStep3D& s : r.steps) {
    r.matched += s.matched;
    r.fallbacks += s.fallback;
    r.still += s.still;
    r.skipped += s.skipped;
  }
  r.ground_truth = truthAtEstimate(cycles.groundTruth6Dof(), r.estimate);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

Trajectory projectToPlane(const Trajectory& trajectory) {
  Trajectory out;
  out.stamps = trajectory.stamps;
  for (const Eigen::Isometry3d& T : trajectory.poses) {
    const Eigen::Vector3d x = T.linear().col(0);
    Eigen::Isometry3d P = Eigen::Isometry3d::Identity();
    P.linear() = Eigen::AngleAxisd(std::atan2(x.y(), x.x()), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    P.translation() = Eigen::Vector3d(T.translation().x(), T.translation().y(), 0);
    out.poses.push_back(P);
  }
  return out;
}

}  // namespace radar_ndt

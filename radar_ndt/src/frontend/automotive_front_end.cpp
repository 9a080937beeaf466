#include "radar_ndt/frontend/automotive_front_end.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "radar_ndt/frontend/probabilistic_submap.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

void AutomotiveFrontEndOptions::validate() const {
  checkFields(*this, "AutomotiveFrontEndOptions");
}

namespace {

/// Where each sweep's points lie in the cycle's cloud, and how long before the reference time it was.
struct SweepRuns {
  std::vector<std::size_t> end;  ///< all[end[s-1] .. end[s]) came from sweep s
  std::vector<float> dt;         ///< t_ref − t_sweep (s), as the points' time_offset stores it
};

/// 1. Every sweep into the vehicle frame (at its own time), with its point covariances. Planar: z
/// (the mounting height, not an elevation: the ARS408 measures none) is set to 0.
SweepRuns sweepsToVehicle(const RadarCycle& cycle, const AutomotiveFrontEndOptions& o,
                          std::vector<SensorMounting>& mountings, pcl::PointCloud<PointRadar>& all) {
  SweepRuns runs;
  for (const auto& sweep : cycle.sweeps) {
    if (sweep.sensor_id >= mountings.size()) mountings.resize(sweep.sensor_id + 1u);
    mountings[sweep.sensor_id] = toMounting(sweep.sensor_to_vehicle);
    const std::size_t begin = all.size();
    pcl::PointCloud<PointRadar> pts = sweep.points;
    setPointCovariances(pts, mountings[sweep.sensor_id].yaw, o.covariance_model, o.polar);
    all.insert(all.end(), pts.begin(), pts.end());
    const float dt = static_cast<float>(1e-6 * static_cast<double>(cycle.timestamp_us - sweep.timestamp_us));
    for (std::size_t i = begin; i < all.size(); ++i) {
      PointRadar& p = all[i];
      const Eigen::Vector3d q = sweep.sensor_to_vehicle * Eigen::Vector3d(p.x, p.y, p.z);
      p.x = static_cast<float>(q.x());
      p.y = static_cast<float>(q.y());
      p.z = 0.f;
      p.sensor_id = sweep.sensor_id;
      p.time_offset = -dt;
    }
    runs.end.push_back(all.size());
    runs.dt.push_back(dt);
  }
  return runs;
}

/// 3. The detections kept: those that agree with the ego-velocity `v` (all of them when moving
/// detections are kept or there is no velocity at all).
pcl::Indices staticDetections(const pcl::PointCloud<PointRadar>::Ptr& all, const Eigen::Vector3d& v, bool remove,
                              const std::vector<SensorMounting>& mountings, double threshold) {
  pcl::Indices keep;
  if (remove) {
    DopplerOutlierRemoval<PointRadar> filter;
    filter.setInputCloud(all);
    filter.setEgoVelocity(v);
    filter.setMountings(mountings);
    filter.setThreshold(threshold);
    filter.filter(keep);
  } else {
    keep.resize(all->size());
    for (std::size_t i = 0; i < all->size(); ++i) keep[i] = static_cast<pcl::index_t>(i);
  }
  return keep;
}

/// 4. Each sweep's kept points to the reference time: the vehicle moved by exp(v·dt) since the
/// sweep (kept indices are increasing, so each sweep's points are one run of `keep`).
void toReferenceTime(const pcl::PointCloud<PointRadar>& all, const pcl::Indices& keep, const SweepRuns& runs,
                     const Eigen::Vector3d& v, bool compensate, pcl::PointCloud<PointRadar>& cloud) {
  cloud.reserve(keep.size());
  std::size_t k = 0;
  for (std::size_t s = 0; s < runs.end.size(); ++s) {
    const std::size_t first = cloud.size();
    for (; k < keep.size() && static_cast<std::size_t>(keep[k]) < runs.end[s]; ++k) cloud.push_back(all[keep[k]]);
    const double dt = runs.dt[s];
    if (!compensate || dt == 0.0 || first == cloud.size()) continue;
    pcl::PointCloud<PointRadar> run;
    run.assign(cloud.begin() + static_cast<std::ptrdiff_t>(first), cloud.end(), 1);
    transformWithUncertainty(run, integrateVelocity(v, dt), Eigen::Matrix3d::Zero());
    std::copy(run.begin(), run.end(), cloud.begin() + static_cast<std::ptrdiff_t>(first));
  }
  cloud.width = static_cast<std::uint32_t>(cloud.size());
  cloud.height = 1;
  cloud.is_dense = true;
}

}  // namespace

ProcessedCycle AutomotiveFrontEnd::process(const RadarCycle& cycle, const EgoVelocity* fallback) const {
  ProcessedCycle out;
  out.timestamp_us = cycle.timestamp_us;
  pcl::PointCloud<PointRadar>::Ptr all(new pcl::PointCloud<PointRadar>);
  const SweepRuns runs = sweepsToVehicle(cycle, options_, out.mountings, *all);
  out.raw_points = all->size();
  // 2. Ego-velocity from the Doppler of all radars (RANSAC), 3. moving detections removed.
  const EgoVelocityEstimator estimator(options_.ego_velocity);
  out.ego = estimator.estimate(*all, out.mountings);
  Eigen::Vector3d v = out.ego.velocity;
  if (!out.ego.valid && fallback) v = fallback->velocity;
  const pcl::Indices keep = staticDetections(all, v, options_.remove_moving && (out.ego.valid || fallback),
                                             out.mountings, options_.ego_velocity.inlier_threshold);
  out.removed_moving = all->size() - keep.size();
  toReferenceTime(*all, keep, runs, v, options_.compensate_time, *out.cloud);
  return out;
}

}  // namespace radar_ndt

#pragma once
// Removes detections whose Doppler disagrees with the ego-velocity (moving objects, ghosts,
// multipath), as a PCL filter: setInputCloud, setNegative, filter(cloud) or filter(indices), the
// way PCL users compose pcl::PassThrough and friends.

#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <pcl/filters/filter_indices.h>

#include "radar_ndt/frontend/ego_velocity.h"
#include "radar_ndt/point_types.h"

namespace radar_ndt {

/// Keeps points (in the vehicle frame, with `doppler` and `sensor_id`) whose measured radial
/// velocity is within `threshold` of what a stationary point shows when the vehicle moves with the
/// given ego-velocity. Points of sensors without a valid mounting are removed; points whose Doppler
/// is NaN (not usable: RadarPointFields::keep_doppler) cannot be told moving and are kept.
template <typename PointT = PointRadar>
class DopplerOutlierRemoval : public pcl::FilterIndices<PointT> {
  using Base = pcl::FilterIndices<PointT>;

 public:
  using Ptr = pcl::shared_ptr<DopplerOutlierRemoval<PointT>>;
  using ConstPtr = pcl::shared_ptr<const DopplerOutlierRemoval<PointT>>;

  DopplerOutlierRemoval() { this->filter_name_ = "DopplerOutlierRemoval"; }

  void setEgoVelocity(const Eigen::Vector3d& v) { velocity_ = v; }
  const Eigen::Vector3d& getEgoVelocity() const { return velocity_; }
  void setMountings(const std::vector<SensorMounting>& m) { mountings_ = m; }
  const std::vector<SensorMounting>& getMountings() const { return mountings_; }
  /// Largest accepted |measured − predicted| radial velocity (m/s). Default 0.25.
  void setThreshold(double t) { threshold_ = t; }
  double getThreshold() const { return threshold_; }

 protected:
  using Base::applyFilter;

  void applyFilter(pcl::Indices& indices) override {
    indices.clear();
    if (this->extract_removed_indices_) this->removed_indices_->clear();
    const auto& cloud = *this->input_;
    for (const auto i : *this->indices_) {
      const PointT& p = cloud[i];
      bool keep = false;
      if (std::isnan(p.doppler) && std::isfinite(p.x) && std::isfinite(p.y))
        keep = true;  // no usable Doppler (RadarPointFields::keep_doppler): it cannot be told moving
      else if (p.sensor_id < mountings_.size() && mountings_[p.sensor_id].valid && std::isfinite(p.doppler) &&
               std::isfinite(p.x) && std::isfinite(p.y))
        keep = std::abs(p.doppler - predictedDoppler(mountings_[p.sensor_id], p.x, p.y, velocity_)) <= threshold_;
      if (keep != this->negative_)
        indices.push_back(i);
      else if (this->extract_removed_indices_)
        this->removed_indices_->push_back(i);
    }
  }

 private:
  Eigen::Vector3d velocity_ = Eigen::Vector3d::Zero();
  std::vector<SensorMounting> mountings_;
  double threshold_ = 0.25;
};

}  // namespace radar_ndt

// pcl::FilterIndices<PointRadar>'s templates are compiled once, in radar_ndt/src/doppler_outlier_removal.cpp.
extern template class pcl::Filter<radar_ndt::PointRadar>;
extern template class pcl::FilterIndices<radar_ndt::PointRadar>;
extern template class radar_ndt::DopplerOutlierRemoval<radar_ndt::PointRadar>;

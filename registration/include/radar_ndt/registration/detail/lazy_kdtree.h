#pragma once
// radar_ndt::detail::LazyKdTree: the kd-tree pcl::Registration holds for its target, built only
// when first searched.

#include <pcl/search/kdtree.h>

namespace radar_ndt {
namespace detail {

/// pcl::search::KdTree that builds its tree only when first searched. pcl::Registration::align
/// rebuilds the target kd-tree for every new target; NDT never searches it, so the only user left
/// is pcl::Registration::getFitnessScore(), which then pays for the tree when (and if) it is called.
template <typename PointT>
class LazyKdTree : public pcl::search::KdTree<PointT> {
 public:
  using Base = pcl::search::KdTree<PointT>;
  using typename Base::PointCloudConstPtr;
  using IndicesConstPtr = pcl::IndicesConstPtr;
  using Base::nearestKSearch;
  using Base::radiusSearch;

  void setInputCloud(const PointCloudConstPtr& cloud, const IndicesConstPtr& indices = IndicesConstPtr()) override {
    this->input_ = cloud;
    this->indices_ = indices;
    built_ = false;
  }
  int nearestKSearch(const PointT& point, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override {
    build();
    return Base::nearestKSearch(point, k, k_indices, k_sqr_distances);
  }
  int radiusSearch(const PointT& point, double radius, pcl::Indices& k_indices, std::vector<float>& k_sqr_distances,
                   unsigned int max_nn = 0) const override {
    build();
    return Base::radiusSearch(point, radius, k_indices, k_sqr_distances, max_nn);
  }

 private:
  void build() const {
    if (!built_ && this->input_) {
      const_cast<LazyKdTree*>(this)->Base::setInputCloud(this->input_, this->indices_);
      built_ = true;
    }
  }
  mutable bool built_ = false;
};

}  // namespace detail
}  // namespace radar_ndt

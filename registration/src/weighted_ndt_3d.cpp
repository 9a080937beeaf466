// The one translation unit that compiles WeightedNDT3D (and PCL's base templates for
// PointRadar4D) for the point types the library ships; every other unit sees the extern template
// declarations in the header.
#define RADAR_NDT_WEIGHTED_NDT_3D_INSTANTIATE
#define PCL_NO_PRECOMPILE  // compile PCL's search and kd-tree templates for PointRadar4D here
#include "radar_ndt/registration/weighted_ndt_3d.h"

#include "radar_ndt/registration/impl/weighted_ndt_3d.hpp"

namespace radar_ndt {

void WeightedNDT3DSettings::validate() const {
  if (resolutions.empty())
    throw std::invalid_argument("WeightedNDT3DSettings: resolutions is empty (one grid size at least)");
  checkFields(*this, "WeightedNDT3DSettings");
}

template class WeightedNDT3D<pcl::PointXYZ, pcl::PointXYZ>;
template class WeightedNDT3D<pcl::PointXYZI, pcl::PointXYZI>;
template class WeightedNDT3D<PointRadar4D, PointRadar4D>;

}  // namespace radar_ndt

template class pcl::PCLBase<radar_ndt::PointRadar4D>;
template class pcl::search::KdTree<radar_ndt::PointRadar4D>;
template class pcl::KdTreeFLANN<radar_ndt::PointRadar4D>;
template class pcl::Registration<radar_ndt::PointRadar4D, radar_ndt::PointRadar4D, float>;

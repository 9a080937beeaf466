// The one translation unit that compiles WeightedNDT2D (and its PCL base templates) for the point
// types the library ships; every other unit sees the extern template declarations in the header.
#define RADAR_NDT_WEIGHTED_NDT_2D_INSTANTIATE
#define PCL_NO_PRECOMPILE  // compile PCL's search and kd-tree templates for PointRadar here
#include "radar_ndt/registration/weighted_ndt_2d.h"

#include "radar_ndt/registration/impl/weighted_ndt_2d.hpp"

namespace radar_ndt {

template class WeightedNDT2D<pcl::PointXYZ, pcl::PointXYZ>;
template class WeightedNDT2D<pcl::PointXYZI, pcl::PointXYZI>;
template class WeightedNDT2D<PointRadar, PointRadar>;

}  // namespace radar_ndt

// PCL's templates for the custom point type, compiled once here (PCL precompiles them only for its
// own point types): the Registration base, PCLBase and the kd-tree that Registration holds.
template class pcl::PCLBase<radar_ndt::PointRadar>;
template class pcl::search::KdTree<radar_ndt::PointRadar>;
template class pcl::KdTreeFLANN<radar_ndt::PointRadar>;
template class pcl::Registration<radar_ndt::PointRadar, radar_ndt::PointRadar, float>;

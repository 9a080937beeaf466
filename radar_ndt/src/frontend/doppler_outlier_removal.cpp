#define PCL_NO_PRECOMPILE
#include <pcl/filters/impl/filter.hpp>
#include <pcl/filters/impl/filter_indices.hpp>

#include "radar_ndt/frontend/doppler_outlier_removal.h"

template class pcl::Filter<radar_ndt::PointRadar>;
template class pcl::FilterIndices<radar_ndt::PointRadar>;
template class radar_ndt::DopplerOutlierRemoval<radar_ndt::PointRadar>;

// pcl-icp: pcl::IterativeClosestPoint, the grid as its maximum correspondence distance. PCL's
// template for PointRadar is compiled here, once.
#define PCL_NO_PRECOMPILE
#include <pcl/registration/icp.h>

#include "builtin_matchers.h"

namespace radar_ndt {
namespace matchers {

MatcherEntry pclIcp() {
  return {"pcl-icp", "pcl::IterativeClosestPoint", MatcherUses{}, MatchCalibration::PclIcp,
          [](const MatcherOptions& options) {
            auto r = pcl::make_shared<pcl::IterativeClosestPoint<PointRadar, PointRadar>>();
            r->setMaximumIterations(options.icp_max_iterations);
            r->setTransformationEpsilon(options.icp_transformation_epsilon);
            r->setEuclideanFitnessEpsilon(options.icp_fitness_epsilon);
            return MatcherAdapter(r, options.nominal());
          }};
}

}  // namespace matchers
}  // namespace radar_ndt

#include <pcl/registration/impl/icp.hpp>
template class pcl::IterativeClosestPoint<radar_ndt::PointRadar, radar_ndt::PointRadar>;

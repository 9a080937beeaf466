// pcl-ndt: pcl::NormalDistributionsTransform with the settings it is compared with everywhere
// (applyPclNdtSettings). PCL's template for PointRadar is compiled here, once.
#define PCL_NO_PRECOMPILE
#include <pcl/registration/ndt.h>

#include "builtin_matchers.h"

namespace radar_ndt {
namespace matchers {

MatcherEntry pclNdt() {
  return {"pcl-ndt", "pcl::NormalDistributionsTransform", MatcherUses{}, MatchCalibration::PclNdt,
          [](const MatcherOptions& options) {
            auto r = pcl::make_shared<pcl::NormalDistributionsTransform<PointRadar, PointRadar>>();
            applyPclNdtSettings(*r, options.grid);
            return MatcherAdapter(r, options.nominal());
          }};
}

}  // namespace matchers
}  // namespace radar_ndt

#include <pcl/registration/impl/ndt.hpp>
template class pcl::NormalDistributionsTransform<radar_ndt::PointRadar, radar_ndt::PointRadar>;

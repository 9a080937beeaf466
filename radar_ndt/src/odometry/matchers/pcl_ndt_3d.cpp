// pcl-ndt-3d: pcl::NormalDistributionsTransform on 4D radar points (positions only), with the
// settings docs/results/matcher_3d.md compares it at. PCL's template for PointRadar4D is compiled
// here, once.
#define PCL_NO_PRECOMPILE
#include <pcl/registration/ndt.h>

#include "builtin_matchers_3d.h"

namespace radar_ndt {
namespace matchers {

using PclNdt3D = pcl::NormalDistributionsTransform<PointRadar4D, PointRadar4D>;

Matcher3DEntry pclNdt3D() {
  return {"pcl-ndt-3d", "pcl::NormalDistributionsTransform in 3D", false,
          [](const Matcher3DOptions& o) {
            auto r = std::make_shared<PclNdt3D>();
            r->setResolution(static_cast<float>(o.pcl_ndt_resolution));
            r->setStepSize(o.pcl_ndt_step);
            r->setTransformationEpsilon(o.pcl_ndt_epsilon);
            r->setMaximumIterations(o.pcl_ndt_iterations);
            return std::static_pointer_cast<Registration3D>(r);
          },
          [](const Registration3D& r) { return static_cast<const PclNdt3D&>(r).getFinalNumIteration(); }};
}

}  // namespace matchers
}  // namespace radar_ndt

#include <pcl/registration/impl/ndt.hpp>
template class pcl::NormalDistributionsTransform<radar_ndt::PointRadar4D, radar_ndt::PointRadar4D>;

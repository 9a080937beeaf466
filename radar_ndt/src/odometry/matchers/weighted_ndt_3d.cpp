// pw-ndt-3d: the paper's weighted probabilistic NDT in 3D (radar_ndt::WeightedNDT3D), each
// point's covariance from its radar's range, azimuth and elevation accuracy.
#include "builtin_matchers_3d.h"

namespace radar_ndt {
namespace matchers {

Matcher3DEntry pwNdt3D() {
  return {"pw-ndt-3d", "radar_ndt::WeightedNDT3D: the paper's weighted probabilistic NDT on SE(3)", true,
          [](const Matcher3DOptions& options) {
            auto r = std::make_shared<WeightedNDT3D<PointRadar4D, PointRadar4D>>();
            r->setSettings(options.ndt);
            return std::static_pointer_cast<Registration3D>(r);
          },
          [](const Registration3D& r) {
            return static_cast<const WeightedNDT3D<PointRadar4D, PointRadar4D>&>(r).getFinalNumIteration();
          }};
}

}  // namespace matchers
}  // namespace radar_ndt

// pcl-gicp: pcl::GeneralizedIterativeClosestPoint on 4D radar points (positions only; its own
// covariances from each point's neighbours), PCL's defaults but the correspondence distance
// (docs/results/matcher_3d.md). PCL's template for PointRadar4D is compiled here, once.
#include <pcl/registration/gicp.h>

#include "builtin_matchers_3d.h"

namespace radar_ndt {
namespace matchers {

namespace {

/// PCL's GICP with its last align's iteration count readable (the member is protected), and not
/// run on a cloud of fewer points than the neighbours it takes for each point's covariance: PCL
/// reads k neighbours of every point whether its search found them or not (a sparse 4D scan holds
/// fewer). Such an align does not converge and leaves the guess.
class PclGicp3D : public pcl::GeneralizedIterativeClosestPoint<PointRadar4D, PointRadar4D> {
 public:
  int iterations() const { return nr_iterations_; }

 protected:
  void computeTransformation(PointCloudSource& output, const Matrix4& guess) override {
    const auto k = static_cast<std::size_t>(k_correspondences_);
    if (input_->size() < k || target_->size() < k) {
      converged_ = false;
      nr_iterations_ = 0;
      final_transformation_ = guess;
      pcl::transformPointCloud(*input_, output, guess);
      return;
    }
    pcl::GeneralizedIterativeClosestPoint<PointRadar4D, PointRadar4D>::computeTransformation(output, guess);
  }
};

}  // namespace

Matcher3DEntry pclGicp() {
  return {"pcl-gicp", "pcl::GeneralizedIterativeClosestPoint", false,
          [](const Matcher3DOptions& o) {
            auto r = std::make_shared<PclGicp3D>();
            r->setMaxCorrespondenceDistance(o.gicp_max_correspondence);
            r->setMaximumIterations(o.gicp_iterations);
            return std::static_pointer_cast<Registration3D>(r);
          },
          [](const Registration3D& r) { return static_cast<const PclGicp3D&>(r).iterations(); }};
}

}  // namespace matchers
}  // namespace radar_ndt

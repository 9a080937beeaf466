#define PCL_NO_PRECOMPILE
#include "radar_ndt/odometry/matcher.h"

#include <stdexcept>

#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>

namespace radar_ndt {

Method parseMethod(const std::string& name) {
  if (name == "pw-ndt") return Method::PwNdt;
  if (name == "pcl-ndt") return Method::PclNdt;
  if (name == "pcl-icp") return Method::PclIcp;
  if (name == "doppler") return Method::Doppler;
  if (name == "rapp-ndt") return Method::RappNdt;
  throw std::invalid_argument("unknown method '" + name + "' (pw-ndt, pcl-ndt, pcl-icp, doppler, rapp-ndt)");
}

const char* toString(Method m) {
  switch (m) {
    case Method::PwNdt: return "pw-ndt";
    case Method::PclNdt: return "pcl-ndt";
    case Method::PclIcp: return "pcl-icp";
    case Method::Doppler: return "doppler";
    case Method::RappNdt: return "rapp-ndt";
  }
  return "?";
}

void MatcherOptions::validate() const {
  ours.validate();
  if (ours_max_iterations < 1) throw std::invalid_argument("MatcherOptions: ours_max_iterations must be >= 1");
  if (icp_max_iterations < 1) throw std::invalid_argument("MatcherOptions: icp_max_iterations must be >= 1");
  if (!(icp_transformation_epsilon >= 0) || !(icp_fitness_epsilon >= 0))
    throw std::invalid_argument("MatcherOptions: the ICP epsilons must be >= 0");
}

MatcherAdapter makeMatcher(const MatcherOptions& options, double grid) {
  options.validate();
  if (!(grid > 0) || !std::isfinite(grid)) throw std::invalid_argument("makeMatcher: the grid must be > 0 and finite");
  switch (options.method) {
    case Method::PwNdt:
    case Method::RappNdt: {
      auto r = pcl::make_shared<WeightedNDT2D<PointRadar, PointRadar>>();
      WeightedNDT2DSettings s = options.ours;
      s.resolutions = {static_cast<float>(grid)};
      r->setSettings(s);
      r->setMaximumIterations(options.ours_max_iterations);
      return MatcherAdapter(r);
    }
    case Method::PclNdt: {
      auto r = pcl::make_shared<pcl::NormalDistributionsTransform<PointRadar, PointRadar>>();
      applyPclNdtSettings(*r, grid);
      return MatcherAdapter(r);
    }
    case Method::PclIcp: {
      auto r = pcl::make_shared<pcl::IterativeClosestPoint<PointRadar, PointRadar>>();
      r->setMaxCorrespondenceDistance(grid);
      r->setMaximumIterations(options.icp_max_iterations);
      r->setTransformationEpsilon(options.icp_transformation_epsilon);
      r->setEuclideanFitnessEpsilon(options.icp_fitness_epsilon);
      return MatcherAdapter(r);
    }
    case Method::Doppler: return MatcherAdapter();
  }
  return MatcherAdapter();
}

MatcherAdapter makeMatcher(Method method, double grid) {
  MatcherOptions options;
  options.method = method;
  return makeMatcher(options, grid);
}

}  // namespace radar_ndt

// PCL's matchers for PointRadar, compiled here once.
#include <pcl/registration/impl/icp.hpp>
#include <pcl/registration/impl/ndt.hpp>
template class pcl::IterativeClosestPoint<radar_ndt::PointRadar, radar_ndt::PointRadar>;
template class pcl::NormalDistributionsTransform<radar_ndt::PointRadar, radar_ndt::PointRadar>;

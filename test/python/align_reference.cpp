// The C++ side of the Python module's align test (python/tests/test_registration.py): two Oxford
// scans thresholded with the default front-end and aligned by WeightedNDT2D from (guess_x, 0, 0),
// the result printed exactly (hexadecimal floats), for the test to compare with radar_ndt.align.
// Usage: python_align_reference SCAN_A SCAN_B RESOLUTION POWER_SHIFT GUESS_X

#include <cstdio>
#include <cstdlib>

#include "radar_ndt/frontend/power_threshold.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/registration/weighted_ndt_2d.h"

int main(int argc, char** argv) {
  using namespace radar_ndt;
  if (argc != 6) {
    std::fprintf(stderr, "usage: %s SCAN_A SCAN_B RESOLUTION POWER_SHIFT GUESS_X\n", argv[0]);
    return 2;
  }
  const PowerThreshold front_end;
  pcl::PointCloud<PointRadar>::Ptr target(new pcl::PointCloud<PointRadar>), source(new pcl::PointCloud<PointRadar>);
  front_end.compute(readOxfordPolarPng(argv[1]), *target);
  front_end.compute(readOxfordPolarPng(argv[2]), *source);
  WeightedNDT2D<PointRadar, PointRadar> ndt;
  ndt.setResolution(std::strtof(argv[3], nullptr));
  ndt.setPowerShift(std::strtof(argv[4], nullptr));
  ndt.setInputTarget(target);
  ndt.setInputSource(source);
  pcl::PointCloud<PointRadar> out;
  ndt.align(out, toMatrix4<float>(Pose2(std::strtod(argv[5], nullptr), 0, 0)));
  const WeightedNDT2DResult& r = ndt.getResult();
  std::printf("source_points %zu\ntarget_points %zu\n", source->size(), target->size());
  std::printf("status %s\nconverged %d\niterations %d\n", toString(r.status), r.converged ? 1 : 0, r.iterations);
  std::printf("final_cost %a\n", r.final_cost);
  std::printf("final_transformation");
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) std::printf(" %a", static_cast<double>(r.final_transformation(i, j)));
  std::printf("\ncovariance");
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) std::printf(" %a", r.pose_covariance(i, j));
  std::printf("\nnum_matched_points %zu\n", r.num_matched_points);
  return 0;
}

// libFuzzer target: trajectory files (readTrajectory: auto-detected, which includes Boreas pose
// CSVs, KITTI, TUM, Boreas odometry). The first input byte chooses the format; the rest is the file.
#include <cmath>
#include <cstdint>

#include "fuzz_support.h"
#include "radar_ndt/io/trajectory_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using radar_ndt::TrajectoryFormat;
  using radar_ndt::fuzz::finding;
  if (size < 1) return 0;
  const TrajectoryFormat format = data[0] % 4 == 0   ? TrajectoryFormat::Auto
                                  : data[0] % 4 == 1 ? TrajectoryFormat::Kitti
                                  : data[0] % 4 == 2 ? TrajectoryFormat::Tum
                                                     : TrajectoryFormat::Boreas;
  const std::string path = radar_ndt::fuzz::writeBytes("trajectory.txt", data + 1, size - 1);
  radar_ndt::fuzz::readOrIoError(path, [&] {
    const radar_ndt::Trajectory t = radar_ndt::readTrajectory(path, format);
    if (t.empty()) finding("an empty trajectory was returned instead of an error");
    if (t.hasStamps() && t.stamps.size() != t.poses.size()) finding("stamps and poses differ in count");
    for (std::size_t i = 0; i < t.size(); ++i) {
      if (!t.poses[i].matrix().allFinite()) finding("non-finite pose");
      const Eigen::Matrix3d r = t.poses[i].linear();
      if ((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-2 || r.determinant() < 0.9)
        finding("pose rotation is not a rotation");
      if (t.hasStamps() && (!std::isfinite(t.stamps[i]) || (i > 0 && !(t.stamps[i] > t.stamps[i - 1]))))
        finding("stamps not finite and strictly increasing");
    }
  });
  return 0;
}

// libFuzzer target: View-of-Delft's radar files (io/view_of_delft.h). The first input byte chooses
// the file: a radar .bin, a pose JSON read for one of its three keys, or a calibration text; the
// rest is the file.
#include <cmath>
#include <cstdint>
#include <vector>

#include "fuzz_support.h"
#include "radar_ndt/io/view_of_delft.h"

namespace {

void checkRigid(const Eigen::Isometry3d& T) {
  using radar_ndt::fuzz::finding;
  if (!T.matrix().allFinite()) finding("non-finite transform");
  const Eigen::Matrix3d R = T.linear();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 || R.determinant() < 0.99)
    finding("transform's rotation is not a rotation");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using radar_ndt::fuzz::finding;
  if (size < 1) return 0;
  const int kind = data[0] % 5;
  const std::string path = radar_ndt::fuzz::writeBytes(kind == 0   ? "00000.bin"
                                                       : kind == 4 ? "00000.txt"
                                                                   : "00000.json",
                                                       data + 1, size - 1);
  radar_ndt::fuzz::readOrIoError(path, [&] {
    if (kind == 0) {
      std::vector<float> compensated;
      std::size_t dropped = 0;
      const auto cloud = radar_ndt::readVodRadarBin(path, &compensated, &dropped);
      if (compensated.size() != cloud.size()) finding("v_r_compensated and points differ in count");
      if ((cloud.size() + dropped) * 7 * sizeof(float) != size - 1)
        finding("rows read and dropped do not add up to the file");
      for (const auto& p : cloud)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(p.doppler) ||
            !std::isfinite(p.rcs) || !std::isfinite(p.time_offset))
          finding("a non-finite point was returned");
    } else if (kind == 4) {
      checkRigid(radar_ndt::readVodRadarToCamera(path));
    } else {
      static const char* const keys[] = {"odomToCamera", "mapToCamera", "UTMToCamera"};
      checkRigid(radar_ndt::readVodCameraPose(path, keys[kind - 1]));
    }
  });
  return 0;
}

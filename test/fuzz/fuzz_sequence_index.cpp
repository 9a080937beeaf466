// libFuzzer target: the per-sequence index files, Oxford `radar.timestamps`
// (readOxfordTimestamps) and RADIATE `Navtech_Polar.txt` (readRadiateFrameTimes). The first input
// byte chooses the reader (bit 0) and strict or lenient mode (bit 1); the rest is the file.
#include <cstdint>
#include <vector>

#include "fuzz_support.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/radiate_scan.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using radar_ndt::fuzz::finding;
  if (size < 1) return 0;
  const bool radiate = (data[0] & 1) != 0;
  const std::string path =
      radar_ndt::fuzz::writeBytes(radiate ? "Navtech_Polar.txt" : "radar.timestamps", data + 1, size - 1);
  // Strict (the default), then lenient (bad lines skipped and reported, as a sequence loads it).
  std::vector<radar_ndt::IoError> skipped;
  auto* lenient = (data[0] & 2) != 0 ? &skipped : nullptr;
  radar_ndt::fuzz::readOrIoError(path, [&] {
    if (radiate) {
      const auto frames = radar_ndt::readRadiateFrameTimes(path, lenient);
      for (std::size_t i = 1; i < frames.size(); ++i)
        if (frames[i].stamp_us <= frames[i - 1].stamp_us) finding("RADIATE frame times not strictly increasing");
    } else {
      const auto stamps = radar_ndt::readOxfordTimestamps(path, lenient);
      for (std::size_t i = 1; i < stamps.size(); ++i)
        if (!(stamps[i].stamp > stamps[i - 1].stamp)) finding("Oxford timestamps not strictly increasing");
    }
  });
  for (const auto& e : skipped)
    if (e.file() != path || e.line() == 0)
      radar_ndt::fuzz::finding(std::string("skipped line without file and line: ") + e.what());
  return 0;
}

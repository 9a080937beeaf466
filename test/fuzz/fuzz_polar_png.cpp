// libFuzzer target: Oxford and RADIATE polar PNGs (readOxfordPolarPng, readRadiatePolarPng).
// The first input byte chooses the reader; the rest is the file. Width and azimuth-count checks
// are off so the fuzzer reaches the row decoding behind them.
#include <cmath>
#include <cstdint>

#include "fuzz_support.h"
#include "radar_ndt/io/polar_scan.h"

namespace {

void checkScan(const radar_ndt::PolarScan& s) {
  using radar_ndt::fuzz::finding;
  if (s.azimuths <= 0 || s.bins <= 0) finding("a scan without azimuths or bins was returned");
  const std::size_t n = static_cast<std::size_t>(s.azimuths);
  if (s.power.size() != n * static_cast<std::size_t>(s.bins)) finding("power size != azimuths * bins");
  if (s.angle.size() != n || s.stamp_us.size() != n || s.measured.size() != n) finding("per-azimuth arrays of the wrong size");
  for (std::size_t a = 0; a < n; ++a) {
    if (!std::isfinite(s.angle[a]) || s.angle[a] <= -M_PI - 1e-9 || s.angle[a] > M_PI + 1e-9) finding("azimuth angle out of (-pi, pi]");
    if (a > 0 && s.stamp_us[a] < s.stamp_us[a - 1]) finding("azimuth timestamps go backwards");
  }
  if (!(s.range_resolution > 0.0)) finding("non-positive range resolution");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const bool radiate = (data[0] & 1) != 0;
  const std::string path = radar_ndt::fuzz::writeBytes(radiate ? "000001.png" : "1547120000000000.png", data + 1, size - 1);
  radar_ndt::fuzz::readOrIoError(path, [&] {
    if (radiate) {
      radar_ndt::RadiatePolarOptions options;
      options.expected_azimuths = 0;
      checkScan(radar_ndt::readRadiatePolarPng(path, 1574859771744660, options));
    } else {
      radar_ndt::OxfordPolarOptions options;
      options.expected_bins = 0;
      checkScan(radar_ndt::readOxfordPolarPng(path, options));
    }
  });
  return 0;
}

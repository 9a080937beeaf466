// libFuzzer target: Oxford, Boreas and RADIATE polar PNGs (readOxfordPolarPng, readBoreasPolarPng,
// readRadiatePolarPng). The first input byte chooses the reader (bit 0: RADIATE; else bit 2:
// Boreas) and whether chunk CRCs are repaired (bit 1); the rest is the file. Width and azimuth-count checks are off so
// the fuzzer reaches the row decoding behind them. Every input is also decoded by both PNG decoders (the fast path and
// libpng alone): a file they answer differently (other pixels, or another error) is a finding.
#include <cmath>
#include <cstdint>
#include <vector>

#include <zlib.h>

#include "fuzz_support.h"
#include "radar_ndt/io/boreas_scan.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/png_image.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/io/radiate_scan.h"
#include "radar_ndt/se2.h"

namespace {

void checkScan(const radar_ndt::PolarScan& s) {
  using radar_ndt::fuzz::finding;
  if (s.azimuths <= 0 || s.bins <= 0) finding("a scan without azimuths or bins was returned");
  const std::size_t n = static_cast<std::size_t>(s.azimuths);
  if (s.power.size() != n * static_cast<std::size_t>(s.bins)) finding("power size != azimuths * bins");
  if (s.angle.size() != n || s.stamp_us.size() != n || s.measured.size() != n)
    finding("per-azimuth arrays of the wrong size");
  for (std::size_t a = 0; a < n; ++a) {
    if (!std::isfinite(s.angle[a]) || s.angle[a] <= -radar_ndt::kPi - 1e-9 || s.angle[a] > radar_ndt::kPi + 1e-9)
      finding("azimuth angle out of (-pi, pi]");
    if (a > 0 && s.stamp_us[a] < s.stamp_us[a - 1]) finding("azimuth timestamps go backwards");
  }
  if (!(s.range_resolution > 0.0)) finding("non-positive range resolution");
  if (!s.chirp_up.empty() && s.chirp_up.size() != n) finding("chirp types of the wrong size");
}

/// Rewrites each chunk's CRC to match its bytes (where the chunk fits in the input), so that
/// mutations inside IHDR and IDAT reach the decoder and our row parsing instead of stopping at
/// libpng's CRC check. Bit 1 of the selector byte leaves the CRCs as they are.
std::vector<std::uint8_t> withValidCrcs(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> png(data, data + size);
  std::size_t at = 8;  // after the signature
  while (at + 12 <= png.size()) {
    const std::size_t length =
        (std::size_t{png[at]} << 24) | (std::size_t{png[at + 1]} << 16) | (std::size_t{png[at + 2]} << 8) | png[at + 3];
    if (length > png.size() - at - 12) break;
    const uLong crc = crc32(0L, png.data() + at + 4, static_cast<uInt>(4 + length));
    for (int i = 0; i < 4; ++i)
      png[at + 8 + length + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(crc >> (24 - 8 * i));
    at += 12 + length;
  }
  return png;
}

/// What a decoder makes of a file: its size and pixels, or its error.
std::string decoded(const std::string& path, radar_ndt::PngDecoder decoder) {
  try {
    const radar_ndt::GrayImage img = radar_ndt::readGrayPng(path, decoder);
    return std::to_string(img.width) + "x" + std::to_string(img.height) + ":" +
           std::string(img.pixels.begin(), img.pixels.end());
  } catch (const radar_ndt::IoError& e) {
    return std::string("error: ") + e.what();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const bool radiate = (data[0] & 1) != 0, boreas = !radiate && (data[0] & 4) != 0;
  const char* name = radiate ? "000001.png" : boreas ? "1733239501983835.png" : "1547120000000000.png";
  const std::vector<std::uint8_t> fixed =
      (data[0] & 2) != 0 ? std::vector<std::uint8_t>(data + 1, data + size) : withValidCrcs(data + 1, size - 1);
  const std::string path = radar_ndt::fuzz::writeBytes(name, fixed.data(), fixed.size());
  if (decoded(path, radar_ndt::PngDecoder::Fast) != decoded(path, radar_ndt::PngDecoder::Libpng))
    radar_ndt::fuzz::finding("the PNG fast path and libpng decode the file differently");
  radar_ndt::fuzz::readOrIoError(path, [&] {
    if (boreas) {
      const radar_ndt::PolarScan s = radar_ndt::readBoreasPolarPng(path);
      checkScan(s);
      if (s.range_resolution != radar_ndt::kBoreasBinAfterUpgrade) radar_ndt::fuzz::finding("a 2024 scan's bin");
    } else if (radiate) {
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

// The polar-scan PNG decoder's fast path (png_fast.h: libdeflate and the row filters undone here)
// against libpng: the same pixels on every real scan and on every row filter, the same answer
// (pixels, or the same error) on files of other layouts and on broken files, and the fast path
// really taking the files scans are.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include <gtest/gtest.h>

#include "png_fast.h"
#include "png_support.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/png_image.h"
#include "test_support.h"

using namespace radar_ndt;
using radar_ndt::test::freshTempDir;
using radar_ndt::test::pngChunk;
using radar_ndt::test::pngHeader;
using radar_ndt::test::pngSignature;
using radar_ndt::test::readBytes;
using radar_ndt::test::writeBytes;
using radar_ndt::test::zlibStream;
namespace fs = std::filesystem;

namespace {

const std::string kData = RADAR_NDT_SHARED_DATA;
constexpr std::size_t kMaxPixels = std::size_t{1} << 28;
constexpr std::size_t kMaxInflation = 1100;

/// What a decoder makes of a file: its pixels with the size, or the error's message.
std::string outcome(const std::string& path, PngDecoder decoder) {
  try {
    const GrayImage img = readGrayPng(path, decoder);
    return std::to_string(img.width) + "x" + std::to_string(img.height) + ":" +
           std::string(img.pixels.begin(), img.pixels.end());
  } catch (const IoError& e) {
    return std::string("error: ") + e.what();
  }
}

bool fastPathTakes(const std::string& bytes) {
  int w = 0, h = 0;
  std::vector<std::uint8_t> pixels;
  return detail::decodeCanonicalGrayPng(bytes, kMaxPixels, kMaxInflation, w, h, pixels);
}

/// A grey PNG whose rows carry the given filter types (cycled) over random filtered bytes (any
/// bytes are a valid filtered row), its zlib stream split over IDAT chunks of at most `idat_size`.
std::string filteredPng(int width, int height, const std::vector<int>& types, std::size_t idat_size,
                        unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::string raw;
  for (int y = 0; y < height; ++y) {
    raw.push_back(static_cast<char>(types[static_cast<std::size_t>(y) % types.size()]));
    for (int x = 0; x < width; ++x) raw.push_back(static_cast<char>(rng() & 0xff));
  }
  const std::string z = zlibStream(raw);
  std::string png = pngSignature() + pngHeader(width, height, 8, 0);
  for (std::size_t at = 0; at < z.size(); at += idat_size) png += pngChunk("IDAT", z.substr(at, idat_size));
  return png + pngChunk("IEND", "");
}

/// Every real polar scan in ../shared/data.
std::vector<std::string> realScans() {
  std::vector<std::string> out;
  for (const char* dir :
       {"/oxford-radar-real/radar", "/radiate-tiny-foggy/Navtech_Polar", "/boreas-sample/radar-2024-12-03/radar"}) {
    if (!fs::is_directory(kData + dir)) continue;
    for (const auto& e : fs::directory_iterator(kData + dir))
      if (e.path().extension() == ".png") out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST(PngDecoder, RealScansDecodeToLibpngsPixelsOnTheFastPath) {
  const std::vector<std::string> scans = realScans();
  if (scans.empty()) GTEST_SKIP() << "no real scans under " << kData << " (../shared/data is absent)";
  EXPECT_GE(scans.size(), 20u);
  for (const std::string& path : scans) {
    EXPECT_TRUE(fastPathTakes(readBytes(path))) << path;
    const GrayImage fast = readGrayPng(path, PngDecoder::Fast);
    const GrayImage reference = readGrayPng(path, PngDecoder::Libpng);
    EXPECT_EQ(fast.width, reference.width) << path;
    EXPECT_EQ(fast.height, reference.height) << path;
    EXPECT_TRUE(fast.pixels == reference.pixels) << path;
  }
}

TEST(PngDecoder, EveryRowFilterIsUndoneAsLibpngUndoesIt) {
  const std::string dir = freshTempDir("png_filters");
  int files = 0;
  for (int width : {1, 2, 3, 17, 300})
    for (const std::vector<int>& types : std::vector<std::vector<int>>{{0}, {1}, {2}, {3}, {4}, {4, 3, 2, 1, 0}}) {
      const std::string bytes = filteredPng(width, 7, types, 64, static_cast<unsigned>(width));
      const std::string path = dir + "/f" + std::to_string(files++) + ".png";
      writeBytes(path, bytes);
      EXPECT_TRUE(fastPathTakes(bytes)) << path;
      EXPECT_EQ(outcome(path, PngDecoder::Fast), outcome(path, PngDecoder::Libpng))
          << "width " << width << ", filters " << types.front() << "...";
    }
  // One row filter of each kind by hand: Sub, Up, Average and Paeth over a known row above.
  const std::uint8_t above[4] = {10, 20, 30, 250};
  const std::uint8_t row[4] = {1, 2, 3, 10};
  std::uint8_t out[4];
  ASSERT_TRUE(detail::unfilterRow(1, row, above, out, 4));
  EXPECT_EQ(std::vector<int>(out, out + 4), (std::vector<int>{1, 3, 6, 16}));
  ASSERT_TRUE(detail::unfilterRow(2, row, above, out, 4));
  EXPECT_EQ(std::vector<int>(out, out + 4), (std::vector<int>{11, 22, 33, 4}));  // 250 + 10 wraps
  ASSERT_TRUE(detail::unfilterRow(3, row, above, out, 4));  // + (left + up) / 2: 0+10, 1+20, 15+30, 25+250
  EXPECT_EQ(std::vector<int>(out, out + 4), (std::vector<int>{6, 15, 25, 147}));
  // Paeth (a left, b up, c upper left, p = a + b - c; the nearest of a, b, c, in that order on a
  // tie): x0 p=10 takes b=10; x1 a=60 b=20 c=10 p=70 takes a; x2 a=60 b=22 c=20 takes a (260
  // wraps to 4); x3 a=4 b=40 c=22 p=22 takes c.
  const std::uint8_t paeth_above[4] = {10, 20, 22, 40};
  const std::uint8_t paeth_row[4] = {50, 0, 200, 3};
  ASSERT_TRUE(detail::unfilterRow(4, paeth_row, paeth_above, out, 4));
  EXPECT_EQ(std::vector<int>(out, out + 4), (std::vector<int>{60, 60, 4, 25}));
  // A tie between left and upper left goes to left: x1 a=6 b=12 c=10 p=8, |p-a| = |p-c| = 2.
  const std::uint8_t tie_above[2] = {10, 12};
  const std::uint8_t tie_row[2] = {252, 1};  // x0 takes b: 252 + 10 wraps to 6
  ASSERT_TRUE(detail::unfilterRow(4, tie_row, tie_above, out, 2));
  EXPECT_EQ(std::vector<int>(out, out + 2), (std::vector<int>{6, 7}));
  ASSERT_TRUE(detail::unfilterRow(4, paeth_row, nullptr, out, 4));  // the first row: Paeth is Sub
  EXPECT_EQ(std::vector<int>(out, out + 4), (std::vector<int>{50, 50, 250, 253}));
  EXPECT_FALSE(detail::unfilterRow(5, row, above, out, 4));
  fs::remove_all(dir);
}

TEST(PngDecoder, OtherLayoutsAndWritersGetLibpngsAnswer) {
  // Files the fast path hands to libpng (palette, colour, alpha, interlacing, 16 bits, a zlib
  // window below 32 KiB) or takes with chunks it skips (gAMA, text): the same answer either way.
  const std::string dir = freshTempDir("png_layouts");
  std::vector<std::uint8_t> grey(40 * 9), rgb, deep;
  for (std::size_t i = 0; i < grey.size(); ++i) grey[i] = static_cast<std::uint8_t>((i * 37) % 256);
  for (std::uint8_t v : grey) {
    rgb.insert(rgb.end(), {v, v, v});
    deep.insert(deep.end(), {v, v});
  }
  std::string palette;
  for (int i = 0; i < 256; ++i) palette += std::string(3, static_cast<char>(i));
  std::string raw;
  for (int y = 0; y < 9; ++y) {
    raw.push_back(0);
    raw.append(reinterpret_cast<const char*>(grey.data()) + y * 40, 40);
  }
  const std::string small_window =
      pngSignature() + pngHeader(40, 9, 8, 0) + pngChunk("IDAT", zlibStream(raw, 9)) + pngChunk("IEND", "");
  const std::string text = pngChunk("tEXt", std::string("Software\0test", 13));
  const std::vector<std::tuple<std::string, std::string, bool>> files = {
      {"grey", test::buildPng(40, 9, 8, 0, 1, grey), true},
      {"gamma_text", test::buildPng(40, 9, 8, 0, 1, grey, pngChunk("gAMA", std::string("\0\0\xaf\xc8", 4)) + text),
       true},
      {"palette", test::buildPng(40, 9, 8, 3, 1, grey, pngChunk("PLTE", palette)), false},
      {"rgb", test::buildPng(40, 9, 8, 2, 3, rgb), false},
      {"adam7", test::buildPng(40, 9, 8, 0, 1, grey, "", true), false},
      {"16bit", test::buildPng(40, 9, 16, 0, 2, deep), false},
      {"small_window", small_window, false},
  };
  for (const auto& [name, bytes, fast] : files) {
    const std::string path = dir + "/" + name + ".png";
    writeBytes(path, bytes);
    EXPECT_EQ(fastPathTakes(bytes), fast) << name;
    EXPECT_EQ(outcome(path, PngDecoder::Fast), outcome(path, PngDecoder::Libpng)) << name;
  }
  fs::remove_all(dir);
}

TEST(PngDecoder, BrokenFilesGetLibpngsAnswer) {
  // A small scan with its stream over several IDATs and an ancillary chunk, then broken every way
  // a byte can break it: truncated at every length, every byte changed (CRCs left, so libpng's CRC
  // check speaks; and CRCs repaired, so the change reaches the header, the stream and the filters),
  // and the cases libpng only warns about (a stream longer than the image, a bad Adler-32, an
  // ancillary chunk's bad CRC) or refuses (a bad filter type, IDATs split by another chunk, no IEND).
  const std::string dir = freshTempDir("png_broken");
  const std::string good = [] {
    std::string png = filteredPng(12, 5, {0, 1, 2, 3, 4}, 30);
    const std::size_t idat = png.find("IDAT") - 4;
    return png.substr(0, idat) + pngChunk("tIME", std::string(7, '\1')) + png.substr(idat);
  }();
  ASSERT_TRUE(fastPathTakes(good));
  auto repairCrcs = [](std::string png) {
    for (std::size_t at = 8; at + 12 <= png.size();) {
      const std::size_t n = (std::size_t{static_cast<std::uint8_t>(png[at])} << 24) |
                            (std::size_t{static_cast<std::uint8_t>(png[at + 1])} << 16) |
                            (std::size_t{static_cast<std::uint8_t>(png[at + 2])} << 8) |
                            static_cast<std::uint8_t>(png[at + 3]);
      if (n > png.size() - at - 12) break;
      png.replace(at, n + 12, pngChunk(png.substr(at + 4, 4), png.substr(at + 8, n)));
      at += n + 12;
    }
    return png;
  };
  std::vector<std::string> cases;
  for (std::size_t n = 0; n < good.size(); ++n) cases.push_back(good.substr(0, n));
  for (std::size_t i = 8; i < good.size(); ++i)
    for (char flip : {'\x01', '\x80', '\x55'}) {
      std::string bad = good;
      bad[i] = static_cast<char>(bad[i] ^ flip);
      cases.push_back(bad);
      cases.push_back(repairCrcs(bad));
    }
  std::string raw;
  for (int y = 0; y < 5; ++y) raw += std::string(1, static_cast<char>(y == 3 ? 5 : 1)) + std::string(12, '\7');
  const std::string head = pngSignature() + pngHeader(12, 5, 8, 0);
  std::string z = zlibStream(raw);
  std::string bad_adler = z;
  bad_adler.back() = static_cast<char>(bad_adler.back() ^ 1);
  std::string longer = raw + std::string(13, '\0');
  const std::string iend = pngChunk("IEND", "");
  raw[3 * 13] = 1;  // the bad filter type repaired
  const std::string zz = zlibStream(raw);
  cases.push_back(head + pngChunk("IDAT", z) + iend);                   // filter type 5
  cases.push_back(head + pngChunk("IDAT", bad_adler) + iend);           // Adler-32
  cases.push_back(head + pngChunk("IDAT", zlibStream(longer)) + iend);  // too much data
  cases.push_back(head + pngChunk("IDAT", zz + "xy") + iend);           // bytes after the stream
  cases.push_back(head + pngChunk("IDAT", zz.substr(0, 9)) + pngChunk("tEXt", "a") + pngChunk("IDAT", zz.substr(9)) +
                  iend);                                                       // split IDATs
  cases.push_back(head + pngChunk("IDAT", zz));                                // no IEND
  cases.push_back(head + pngChunk("IDAT", zz) + pngChunk("IEND", "x"));        // IEND with data
  cases.push_back(head + pngChunk("IDAT", "") + pngChunk("IDAT", zz) + iend);  // an empty IDAT
  cases.push_back(head + pngChunk("IDAT", zz) + pngChunk("IDAT", "") + iend);  // and after
  cases.push_back(head + pngChunk("IDAT", zz) + iend + "trailing bytes");      // after IEND
  cases.push_back(head + pngChunk("PLTE", std::string(6, '\0')) + pngChunk("IDAT", zz) + iend);
  cases.push_back(head + pngChunk("CHNK", "x") + pngChunk("IDAT", zz) + iend);  // unknown critical
  cases.push_back(head + pngChunk("bL@K", "x") + pngChunk("IDAT", zz) + iend);  // bad chunk name
  std::string bad_crc = pngChunk("tEXt", "ab");
  bad_crc.back() = static_cast<char>(bad_crc.back() ^ 1);
  cases.push_back(head + bad_crc + pngChunk("IDAT", zz) + iend);  // an ancillary CRC: a warning
  cases.push_back(pngSignature() + pngChunk("tEXt", "ab") + pngHeader(12, 5, 8, 0) + pngChunk("IDAT", zz) + iend);
  for (int bad_width : {0, 1000001})
    cases.push_back(pngSignature() + pngHeader(bad_width, 5, 8, 0) + pngChunk("IDAT", zz) + iend);
  int differ = 0, fast_taken = 0;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const std::string path = dir + "/case" + std::to_string(k) + ".png";
    writeBytes(path, cases[k]);
    fast_taken += fastPathTakes(cases[k]);
    const std::string fast = outcome(path, PngDecoder::Fast), reference = outcome(path, PngDecoder::Libpng);
    if (fast != reference && ++differ <= 5)
      ADD_FAILURE() << "case " << k << ": fast path '" << fast.substr(0, 120) << "', libpng '"
                    << reference.substr(0, 120) << "'";
  }
  EXPECT_EQ(differ, 0) << "of " << cases.size() << " broken files";
  // The ones it takes are the changes that leave a valid file (an ancillary chunk's bytes with its
  // CRC repaired, a changed pixel byte); most go to libpng.
  EXPECT_GT(fast_taken, 0);
  EXPECT_LT(fast_taken, static_cast<int>(cases.size()) / 2);
  fs::remove_all(dir);
}

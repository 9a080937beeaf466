#pragma once
// PNG files built byte by byte, as other tools (or a broken writer) might store them: for the
// tests of the polar-scan decoder.
#include <cstdint>
#include <string>
#include <vector>

#include <zlib.h>

namespace radar_ndt {
namespace test {

inline void appendBe32(std::string& out, std::uint32_t v) {
  for (int i = 3; i >= 0; --i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}

/// A PNG chunk: length, type, data, CRC.
inline std::string pngChunk(const std::string& type, const std::string& data) {
  std::string out;
  appendBe32(out, static_cast<std::uint32_t>(data.size()));
  const std::string body = type + data;
  out += body;
  appendBe32(out, static_cast<std::uint32_t>(
                      crc32(0L, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()))));
  return out;
}

inline std::string pngSignature() {
  return std::string("\x89PNG\r\n\x1a\n", 8);
}

inline std::string pngHeader(int width, int height, int bit_depth, int color_type, bool adam7 = false) {
  std::string ihdr;
  appendBe32(ihdr, static_cast<std::uint32_t>(width));
  appendBe32(ihdr, static_cast<std::uint32_t>(height));
  ihdr += {static_cast<char>(bit_depth), static_cast<char>(color_type), 0, 0, static_cast<char>(adam7 ? 1 : 0)};
  return pngChunk("IHDR", ihdr);
}

/// zlib's compression of `raw` with the given window (15: the 32 KiB window every writer uses).
inline std::string zlibStream(const std::string& raw, int window_bits = 15, int level = 6) {
  z_stream z{};
  deflateInit2(&z, level, Z_DEFLATED, window_bits, 8, Z_DEFAULT_STRATEGY);
  std::string out(deflateBound(&z, static_cast<uLong>(raw.size())), '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(raw.data()));
  z.avail_in = static_cast<uInt>(raw.size());
  z.next_out = reinterpret_cast<Bytef*>(&out[0]);
  z.avail_out = static_cast<uInt>(out.size());
  deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

/// A PNG as another tool might write it: `samples` is width × height pixels of `bytes_per_pixel`
/// bytes each, stored with `bit_depth`/`color_type`, `extra` chunks (gAMA, PLTE, ...) before the
/// data, optionally Adam7-interlaced. Every row uses filter 0.
inline std::string buildPng(int width, int height, int bit_depth, int color_type, int bytes_per_pixel,
                            const std::vector<std::uint8_t>& samples, const std::string& extra = "",
                            bool adam7 = false) {
  std::string raw;
  auto addRow = [&](int y, int x0, int dx) {
    if (x0 >= width) return;
    raw.push_back(0);
    for (int x = x0; x < width; x += dx)
      raw.append(
          reinterpret_cast<const char*>(samples.data()) + (static_cast<std::size_t>(y) * width + x) * bytes_per_pixel,
          bytes_per_pixel);
  };
  if (adam7) {
    const int pass[7][4] = {{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4},
                            {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}};
    for (const auto& p : pass)
      for (int y = p[1]; y < height; y += p[3]) addRow(y, p[0], p[2]);
  } else {
    for (int y = 0; y < height; ++y) addRow(y, 0, 1);
  }
  return pngSignature() + pngHeader(width, height, bit_depth, color_type, adam7) + extra +
         pngChunk("IDAT", zlibStream(raw)) + pngChunk("IEND", "");
}

}  // namespace test
}  // namespace radar_ndt

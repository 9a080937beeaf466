#pragma once
// 8-bit PNG images: the decoder the polar-scan readers share (libdeflate for the files scans are,
// libpng for every other), and an atomic writer.

#include <cstdint>
#include <string>
#include <vector>

namespace radar_ndt {

/// Decodes an 8-bit grayscale PNG into row-major pixels, the samples exactly as stored: gamma and
/// colour-space chunks are ignored (a scan is data, not a picture), alpha is dropped, interlacing
/// is undone, and a file stored as RGB, RGBA or through a palette is taken when every pixel is grey
/// (as tools that write every image in colour leave it). Real colour and other sample depths than 8
/// bits are an IoError naming the file.
struct GrayImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;
};
/// The decoder readGrayPng uses. Fast: the 8-bit grey, non-interlaced files polar scans are are
/// inflated by libdeflate and their row filters undone here, every other file (other layouts, and
/// any file with something unusual or wrong in it) goes to libpng, so the pixels and the errors are
/// libpng's either way. Libpng: libpng for every file (the reference the fast path is tested against).
enum class PngDecoder { Fast, Libpng };
GrayImage readGrayPng(const std::string& path, PngDecoder decoder = PngDecoder::Fast);
/// The same into `image`, reusing its storage (a reader that decodes scan after scan allocates once).
void readGrayPng(const std::string& path, GrayImage& image, PngDecoder decoder = PngDecoder::Fast);
/// Writes an 8-bit grayscale (channels 1) or RGB (channels 3) PNG atomically.
void writePng(const std::string& path, int width, int height, int channels, const std::uint8_t* pixels,
              int compression_level = 6);

}  // namespace radar_ndt

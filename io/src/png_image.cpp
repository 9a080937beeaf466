// The decoder the polar-scan readers share (8-bit samples, exactly as stored; grey taken from colour
// files when every pixel is grey): the fast path (png_fast.h) for the files scans are, libpng's
// classic API for the rest; and the writer.
#include "radar_ndt/io/png_image.h"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <new>

#include "png_fast.h"
#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/io_error.h"
#include "read_file.h"

namespace radar_ndt {
namespace {

// Upper bound on decoded pixels (a 16-bit-wide, 2^16-row image): a PNG header can declare any size,
// and a tiny file can inflate to gigabytes; real Navtech scans are 400 × 3779.
constexpr std::size_t kMaxPixels = std::size_t{1} << 28;
constexpr std::size_t kMaxInflation = 1100;  // deflate's limit is 1032:1, plus PNG's per-row filter byte

// libpng's classic API reports errors by longjmp. Its error pointer is the message buffer (256
// bytes); nothing with a destructor lives between setjmp and the calls that can jump.
void pngError(png_structp png, png_const_charp msg) {
  std::snprintf(static_cast<char*>(png_get_error_ptr(png)), 256, "%s", msg);
  png_longjmp(png, 1);
}
void pngWarning(png_structp, png_const_charp) {}

struct PngReadContext {
  const std::string* data = nullptr;
  std::size_t pos = 0;
  char message[256] = {0};
  std::string refusal;  ///< set when the file is a valid PNG this reader does not take
  png_uint_32 width = 0, height = 0;
  std::vector<std::uint8_t> samples;  ///< width × height × channels after the transforms
  std::vector<png_bytep> rows;
  int channels = 0;
};

void pngRead(png_structp png, png_bytep out, png_size_t length) {
  auto* ctx = static_cast<PngReadContext*>(png_get_io_ptr(png));
  if (length > ctx->data->size() - ctx->pos) png_error(png, "the file ends inside the image data");
  std::memcpy(out, ctx->data->data() + ctx->pos, length);
  ctx->pos += length;
}

// What this reader refuses of a valid header: sample depths other than 8 bits (palettes aside),
// and sizes no scan has or the file cannot hold; "" when it takes the image.
std::string refusalOf(const PngReadContext& ctx, int bit_depth, bool palette) {
  if (bit_depth != 8 && !palette)
    return "expected an 8-bit grayscale PNG, found " + std::to_string(bit_depth) + "-bit samples";
  const std::size_t pixels = static_cast<std::size_t>(ctx.width) * ctx.height;
  const std::string size = std::to_string(ctx.width) + "x" + std::to_string(ctx.height);
  if (pixels > kMaxPixels) return "PNG declares an absurd size " + size;
  // zlib inflates at most ~1032:1, so a header that declares more pixels than the file can hold
  // is refused before the image is allocated.
  if (pixels / kMaxInflation > ctx.data->size())
    return "PNG declares " + size + " pixels, more than its " + std::to_string(ctx.data->size()) +
           " bytes can hold (truncated?)";
  return "";
}

// Expands the samples to 1 or 3 channels of 8 bits (palette through its colours, alpha dropped,
// interlacing undone) and allocates the rows. False with ctx.refusal set when out of memory; a
// layout libpng cannot give is a libpng error (longjmp).
bool prepareSamples(png_structp png, png_infop info, PngReadContext& ctx, bool palette) {
  if (palette) png_set_palette_to_rgb(png);
  png_set_strip_alpha(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  ctx.channels = png_get_channels(png, info);
  if ((ctx.channels != 1 && ctx.channels != 3) ||
      png_get_rowbytes(png, info) != static_cast<std::size_t>(ctx.width) * ctx.channels)
    png_error(png, "unexpected sample layout after expansion");
  try {
    ctx.samples.resize(static_cast<std::size_t>(ctx.width) * ctx.height * ctx.channels);
    ctx.rows.resize(ctx.height);
  } catch (const std::bad_alloc&) {
    ctx.refusal = "out of memory for a " + std::to_string(ctx.width) + "x" + std::to_string(ctx.height) + " image";
    return false;
  }
  for (png_uint_32 r = 0; r < ctx.height; ++r)
    ctx.rows[r] = ctx.samples.data() + static_cast<std::size_t>(r) * ctx.width * ctx.channels;
  return true;
}

// Decodes the samples exactly as stored: no gamma, colour-space or background handling (libpng's
// simplified API converts 8-bit output to sRGB, so a file with a gAMA chunk, as some tools write,
// would come out with altered powers and timestamps). Returns false on a libpng error (message in
// ctx) or a refusal (ctx.refusal); `header_done` tells which stage failed. Nothing with a
// destructor lives in this frame between setjmp and the calls that can jump.
bool decodePngSamples(PngReadContext& ctx, bool& header_done) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, ctx.message, pngError, pngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    std::snprintf(ctx.message, sizeof ctx.message, "out of memory");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_set_read_fn(png, &ctx, pngRead);
  png_read_info(png, info);
  header_done = true;
  int bit_depth = 0, color_type = 0, interlace = 0;
  png_get_IHDR(png, info, &ctx.width, &ctx.height, &bit_depth, &color_type, &interlace, nullptr, nullptr);
  const bool palette = color_type == PNG_COLOR_TYPE_PALETTE;
  ctx.refusal = refusalOf(ctx, bit_depth, palette);
  if (!ctx.refusal.empty() || !prepareSamples(png, info, ctx, palette)) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_read_image(png, ctx.rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

void decodeGrayPng(const std::string& path, const std::string& data, PngDecoder decoder, GrayImage& out) {
  static const unsigned char kSignature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
  if (data.empty()) throw IoError(path, "empty file, expected a PNG image");
  if (data.size() < 8 || std::memcmp(data.data(), kSignature, 8) != 0)
    throw IoError(path, "not a PNG file (bad signature)");
  if (decoder == PngDecoder::Fast &&
      detail::decodeCanonicalGrayPng(data, kMaxPixels, kMaxInflation, out.width, out.height, out.pixels))
    return;
  PngReadContext ctx;
  ctx.data = &data;
  bool header_done = false;
  if (!decodePngSamples(ctx, header_done)) {
    if (!ctx.refusal.empty()) throw IoError(path, ctx.refusal);
    throw IoError(path,
                  std::string(header_done ? "corrupt or truncated PNG data: " : "invalid PNG header: ") + ctx.message);
  }
  out.width = static_cast<int>(ctx.width);
  out.height = static_cast<int>(ctx.height);
  if (ctx.channels == 1) {
    out.pixels = std::move(ctx.samples);
    return;
  }
  // A colour (or palette) file is taken when it is grey, as tools that write every image as RGB
  // leave it; real colour cannot be a radar scan.
  const std::size_t pixels = static_cast<std::size_t>(ctx.width) * ctx.height;
  out.pixels.resize(pixels);
  for (std::size_t i = 0; i < pixels; ++i) {
    const std::uint8_t* p = ctx.samples.data() + 3 * i;
    if (p[0] != p[1] || p[0] != p[2])
      throw IoError(path, "expected an 8-bit grayscale PNG, found a colour image (pixel " +
                              std::to_string(i % ctx.width) + ", " + std::to_string(i / ctx.width) + " is RGB " +
                              std::to_string(p[0]) + "," + std::to_string(p[1]) + "," + std::to_string(p[2]) + ")");
    out.pixels[i] = p[0];
  }
}

// libpng's classic writer: its error pointer is the message buffer, its io pointer the output.
void pngWrite(png_structp png, png_bytep data, png_size_t length) {
  static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), length);
}
void pngFlush(png_structp) {}

bool encodePng(std::string& out, int width, int height, int channels, const std::uint8_t* pixels, int level,
               char* message) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, message, pngError, pngWarning);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, &out, pngWrite, pngFlush);
  png_set_compression_level(png, level);
  // PNG's adaptive filters cost more than the zlib level saves on speckled radar images.
  png_set_filter(png, PNG_FILTER_TYPE_BASE, level <= 3 ? PNG_FILTER_SUB : PNG_ALL_FILTERS);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int r = 0; r < height; ++r)
    png_write_row(png, const_cast<png_bytep>(pixels + static_cast<std::size_t>(r) * width * channels));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

void readGrayPng(const std::string& path, GrayImage& image, PngDecoder decoder) {
  thread_local std::string bytes;  // the file, its storage kept from one scan to the next
  detail::readWholeFile(path, bytes);
  decodeGrayPng(path, bytes, decoder, image);
}

GrayImage readGrayPng(const std::string& path, PngDecoder decoder) {
  GrayImage image;
  readGrayPng(path, image, decoder);
  return image;
}

void writePng(const std::string& path, int width, int height, int channels, const std::uint8_t* pixels,
              int compression_level) {
  if (width <= 0 || height <= 0 || (channels != 1 && channels != 3))
    throw IoError(path, "cannot write a PNG of " + std::to_string(width) + "x" + std::to_string(height) + "x" +
                            std::to_string(channels));
  std::string out;
  out.reserve(static_cast<std::size_t>(width) * height * channels / 2 + 1024);
  char message[256] = {0};
  if (!encodePng(out, width, height, channels, pixels, compression_level, message))
    throw IoError(path, std::string("PNG encoding failed: ") + message);
  writeFileAtomically(path, out);
}

}  // namespace radar_ndt

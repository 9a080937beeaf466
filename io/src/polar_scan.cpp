#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/se2.h"

#include <png.h>

#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <new>
#include <sstream>

#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/io_error.h"
#include "read_file.h"

namespace radar_ndt {
namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;
constexpr int kOxfordMetaBytes = 11;  // int64 timestamp, uint16 encoder, uint8 flag
// Upper bound on decoded pixels (a 16-bit-wide, 2^16-row image): a PNG header can declare any size,
// and a tiny file can inflate to gigabytes; real Navtech scans are 400 × 3779.
constexpr std::size_t kMaxPixels = std::size_t{1} << 28;
constexpr std::size_t kMaxInflation = 1100;  // deflate's limit is 1032:1, plus PNG's per-row filter byte

double wrapPi(double a) {
  a = std::fmod(a, kTwoPi);
  if (a > kPi) a -= kTwoPi;
  if (a <= -kPi) a += kTwoPi;
  return a;
}

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

// Decodes the samples exactly as stored: no gamma, colour-space or background handling (libpng's
// simplified API converts 8-bit output to sRGB, so a file with a gAMA chunk, as some tools write,
// would come out with altered powers and timestamps). Palette images are expanded through their
// palette, alpha is dropped, interlaced images are de-interlaced. Returns false on a libpng error
// (message in ctx) or a refusal (ctx.refusal); `header_done` tells which stage failed.
bool decodePngSamples(PngReadContext& ctx, bool& header_done) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, ctx.message, pngError, pngWarning);
  if (!png) {
    std::snprintf(ctx.message, sizeof ctx.message, "out of memory");
    return false;
  }
  png_infop info = png_create_info_struct(png);
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
  if (bit_depth != 8 && !palette) {
    ctx.refusal = "expected an 8-bit grayscale PNG, found " + std::to_string(bit_depth) + "-bit samples";
  } else {
    const std::size_t pixels = static_cast<std::size_t>(ctx.width) * ctx.height;
    if (pixels > kMaxPixels) {
      ctx.refusal = "PNG declares an absurd size " + std::to_string(ctx.width) + "x" + std::to_string(ctx.height);
    } else if (pixels / kMaxInflation > ctx.data->size()) {
      // zlib inflates at most ~1032:1, so a header that declares more pixels than the file can
      // hold is refused before the image is allocated.
      ctx.refusal = "PNG declares " + std::to_string(ctx.width) + "x" + std::to_string(ctx.height) +
                    " pixels, more than its " + std::to_string(ctx.data->size()) + " bytes can hold (truncated?)";
    }
  }
  if (!ctx.refusal.empty()) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
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
    png_destroy_read_struct(&png, &info, nullptr);
    ctx.refusal = "out of memory for a " + std::to_string(ctx.width) + "x" + std::to_string(ctx.height) + " image";
    return false;
  }
  for (png_uint_32 r = 0; r < ctx.height; ++r)
    ctx.rows[r] = ctx.samples.data() + static_cast<std::size_t>(r) * ctx.width * ctx.channels;
  png_read_image(png, ctx.rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

GrayImage decodeGrayPng(const std::string& path, const std::string& data) {
  static const unsigned char kSignature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
  if (data.empty()) throw IoError(path, "empty file, expected a PNG image");
  if (data.size() < 8 || std::memcmp(data.data(), kSignature, 8) != 0)
    throw IoError(path, "not a PNG file (bad signature)");
  PngReadContext ctx;
  ctx.data = &data;
  bool header_done = false;
  if (!decodePngSamples(ctx, header_done)) {
    if (!ctx.refusal.empty()) throw IoError(path, ctx.refusal);
    throw IoError(path,
                  std::string(header_done ? "corrupt or truncated PNG data: " : "invalid PNG header: ") + ctx.message);
  }
  GrayImage out;
  out.width = static_cast<int>(ctx.width);
  out.height = static_cast<int>(ctx.height);
  if (ctx.channels == 1) {
    out.pixels = std::move(ctx.samples);
    return out;
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
  return out;
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

std::int64_t readLe64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return static_cast<std::int64_t>(v);
}
std::uint16_t readLe16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}

bool stemAsStamp(const std::string& path, std::int64_t& stamp) {
  const std::size_t slash = path.find_last_of('/');
  std::string stem = path.substr(slash == std::string::npos ? 0 : slash + 1);
  const std::size_t dot = stem.find('.');
  if (dot != std::string::npos) stem = stem.substr(0, dot);
  if (stem.empty() || stem.size() > 18) return false;
  for (char c : stem)
    if (c < '0' || c > '9') return false;
  stamp = std::stoll(stem);
  return true;
}

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream ss(line);
  while (std::getline(ss, cell, ',')) {
    while (!cell.empty() && (cell.back() == '\r' || cell.back() == ' ')) cell.pop_back();
    while (!cell.empty() && cell.front() == ' ') cell.erase(cell.begin());
    out.push_back(cell);
  }
  return out;
}

std::int64_t parseInt64(const std::string& path, std::size_t line, const std::string& token, const char* what) {
  try {
    std::size_t used = 0;
    const long long v = std::stoll(token, &used);
    if (used != token.size()) throw std::invalid_argument(token);
    return v;
  } catch (const std::exception&) {
    throw IoError(path, line, std::string("cannot parse ") + what + " '" + token + "' as an integer");
  }
}

double parseFinite(const std::string& path, std::size_t line, const std::string& token, const char* what) {
  double v = 0.0;
  try {
    std::size_t used = 0;
    v = std::stod(token, &used);
    if (used != token.size()) throw std::invalid_argument(token);
  } catch (const std::exception&) {
    throw IoError(path, line, std::string("cannot parse ") + what + " '" + token + "' as a number");
  }
  if (!std::isfinite(v)) throw IoError(path, line, std::string(what) + " is not finite");
  return v;
}

}  // namespace

double PolarConvention::toVehicleAngle(double sensor_azimuth) const {
  return wrapPi(azimuth_zero + (clockwise ? -sensor_azimuth : sensor_azimuth));
}

double PolarConvention::toSensorAzimuth(double vehicle_angle) const {
  double a = clockwise ? azimuth_zero - vehicle_angle : vehicle_angle - azimuth_zero;
  a = std::fmod(a, kTwoPi);
  if (a < 0) a += kTwoPi;
  return a;
}

GrayImage readGrayPng(const std::string& path) {
  return decodeGrayPng(path, detail::readWholeFile(path));
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

PolarScan readOxfordPolarPng(const std::string& path, const OxfordPolarOptions& options) {
  const GrayImage img = readGrayPng(path);
  if (img.width <= kOxfordMetaBytes)
    throw IoError(path, "image is " + std::to_string(img.width) +
                            " pixels wide: an Oxford radar row needs 11 metadata bytes and the range bins");
  const int bins = img.width - kOxfordMetaBytes;
  if (options.expected_bins > 0 && bins != options.expected_bins)
    throw IoError(path, "image is " + std::to_string(img.width) + " pixels wide, expected " +
                            std::to_string(options.expected_bins + kOxfordMetaBytes) + " (11 metadata bytes + " +
                            std::to_string(options.expected_bins) + " range bins)");
  if (options.encoder_size <= 0) throw IoError(path, "encoder_size must be positive");
  PolarScan scan;
  scan.azimuths = img.height;
  scan.bins = bins;
  scan.range_resolution = options.convention.range_resolution;
  scan.range_offset_bins = options.convention.range_offset_bins;
  scan.power.resize(static_cast<std::size_t>(scan.azimuths) * bins);
  scan.angle.resize(scan.azimuths);
  scan.stamp_us.resize(scan.azimuths);
  scan.measured.resize(scan.azimuths);
  scan.encoder.resize(scan.azimuths);
  for (int a = 0; a < scan.azimuths; ++a) {
    const std::uint8_t* row = img.pixels.data() + static_cast<std::size_t>(a) * img.width;
    scan.stamp_us[a] = readLe64(row);
    scan.encoder[a] = readLe16(row + 8);
    scan.measured[a] = row[10] == 255;
    if (scan.encoder[a] >= options.encoder_size)
      throw IoError(path, "row " + std::to_string(a) + ": encoder count " + std::to_string(scan.encoder[a]) +
                              " outside [0, " + std::to_string(options.encoder_size) + ")");
    if (a > 0 && scan.stamp_us[a] < scan.stamp_us[a - 1])
      throw IoError(path, "row " + std::to_string(a) + ": azimuth timestamps out of order (" +
                              std::to_string(scan.stamp_us[a]) + " after " + std::to_string(scan.stamp_us[a - 1]) +
                              ")");
    scan.angle[a] = options.convention.toVehicleAngle(kTwoPi * scan.encoder[a] / options.encoder_size);
    std::memcpy(scan.row(a), row + kOxfordMetaBytes, static_cast<std::size_t>(bins));
  }
  if (!stemAsStamp(path, scan.stamp)) scan.stamp = scan.stamp_us.front();
  return scan;
}

void writeOxfordPolarPng(const std::string& path, const PolarScan& scan, const OxfordPolarOptions& options,
                         int compression_level) {
  if (scan.azimuths <= 0 || scan.bins <= 0 ||
      scan.power.size() != static_cast<std::size_t>(scan.azimuths) * scan.bins ||
      scan.angle.size() != static_cast<std::size_t>(scan.azimuths) ||
      scan.stamp_us.size() != static_cast<std::size_t>(scan.azimuths))
    throw IoError(path, "inconsistent PolarScan (sizes of power, angle and stamp_us do not match)");
  const int width = scan.bins + kOxfordMetaBytes;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * scan.azimuths);
  for (int a = 0; a < scan.azimuths; ++a) {
    std::uint8_t* row = pixels.data() + static_cast<std::size_t>(a) * width;
    const auto t = static_cast<std::uint64_t>(scan.stamp_us[a]);
    for (int i = 0; i < 8; ++i) row[i] = static_cast<std::uint8_t>(t >> (8 * i));
    int enc = scan.encoder.size() == static_cast<std::size_t>(scan.azimuths)
                  ? scan.encoder[a]
                  : static_cast<int>(
                        std::lround(options.convention.toSensorAzimuth(scan.angle[a]) / kTwoPi * options.encoder_size));
    enc %= options.encoder_size;
    row[8] = static_cast<std::uint8_t>(enc & 0xff);
    row[9] = static_cast<std::uint8_t>((enc >> 8) & 0xff);
    row[10] = scan.measured.empty() || scan.measured[a] ? 255 : 0;
    std::memcpy(row + kOxfordMetaBytes, scan.row(a), static_cast<std::size_t>(scan.bins));
  }
  writePng(path, width, scan.azimuths, 1, pixels.data(), compression_level);
}

PolarScan readRadiatePolarPng(const std::string& path, std::int64_t frame_time_us, const RadiatePolarOptions& options) {
  const GrayImage img = readGrayPng(path);
  if (options.expected_azimuths > 0 && img.width != options.expected_azimuths)
    throw IoError(path, "image is " + std::to_string(img.width) + " pixels wide, expected " +
                            std::to_string(options.expected_azimuths) + " azimuth columns");
  PolarScan scan;
  scan.azimuths = img.width;
  scan.bins = img.height;
  scan.range_resolution = options.convention.range_resolution;
  scan.range_offset_bins = options.convention.range_offset_bins;
  scan.stamp = frame_time_us;
  scan.power.resize(static_cast<std::size_t>(scan.azimuths) * scan.bins);
  scan.angle.resize(scan.azimuths);
  scan.stamp_us.resize(scan.azimuths);
  scan.measured.assign(scan.azimuths, 1);
  const double period_us = options.sweep_period * 1e6;
  for (int a = 0; a < scan.azimuths; ++a) {
    scan.angle[a] = options.convention.toVehicleAngle(kTwoPi * a / scan.azimuths);
    scan.stamp_us[a] = frame_time_us + static_cast<std::int64_t>(std::llround(period_us * a / scan.azimuths));
    std::uint8_t* dst = scan.row(a);
    for (int b = 0; b < scan.bins; ++b) dst[b] = img.pixels[static_cast<std::size_t>(b) * img.width + a];
  }
  return scan;
}

std::vector<OxfordStamp> readOxfordTimestamps(const std::string& path, std::vector<IoError>* skipped) {
  std::ifstream in(path);
  if (!in) throw IoError(path, "cannot open file");
  std::vector<OxfordStamp> out;
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    ++n;
    try {
      std::istringstream ss(line);
      std::string t, v, extra;
      if (!(ss >> t)) continue;  // blank line
      if (!(ss >> v) || (ss >> extra)) throw IoError(path, n, "expected '<timestamp> <valid>', found '" + line + "'");
      OxfordStamp s;
      s.stamp = parseInt64(path, n, t, "timestamp");
      const std::int64_t valid = parseInt64(path, n, v, "valid flag");
      if (valid != 0 && valid != 1) throw IoError(path, n, "valid flag must be 0 or 1, found " + v);
      s.valid = valid == 1;
      if (!out.empty() && s.stamp <= out.back().stamp)
        throw IoError(path, n,
                      std::string(s.stamp == out.back().stamp ? "duplicated timestamp" : "timestamps out of order") +
                          " (" + t + " after " + std::to_string(out.back().stamp) + ")");
      out.push_back(s);
    } catch (const IoError& e) {
      if (!skipped) throw;
      skipped->push_back(e);
    }
  }
  return out;
}

void writeOxfordTimestamps(const std::string& path, const std::vector<OxfordStamp>& stamps) {
  std::string s;
  for (const auto& t : stamps) s += std::to_string(t.stamp) + (t.valid ? " 1\n" : " 0\n");
  writeFileAtomically(path, s);
}

std::vector<OxfordRelativePose> readOxfordRadarOdometry(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path, "cannot open file");
  std::string line;
  if (!std::getline(in, line)) throw IoError(path, "empty file, expected a header line");
  const std::vector<std::string> header = splitCsv(line);
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
  for (const char* need : {"source_timestamp", "destination_timestamp", "x", "y", "z", "roll", "pitch", "yaw"})
    if (!col.count(need)) throw IoError(path, 1, std::string("header has no column '") + need + "'");
  const bool has_radar = col.count("source_radar_timestamp") && col.count("destination_radar_timestamp");
  std::vector<OxfordRelativePose> out;
  std::size_t n = 1;
  while (std::getline(in, line)) {
    ++n;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<std::string> cells = splitCsv(line);
    if (cells.size() != header.size())
      throw IoError(path, n,
                    "expected " + std::to_string(header.size()) + " columns, found " + std::to_string(cells.size()));
    OxfordRelativePose r;
    r.source = parseInt64(path, n, cells[col["source_timestamp"]], "source_timestamp");
    r.destination = parseInt64(path, n, cells[col["destination_timestamp"]], "destination_timestamp");
    r.x = parseFinite(path, n, cells[col["x"]], "x");
    r.y = parseFinite(path, n, cells[col["y"]], "y");
    r.z = parseFinite(path, n, cells[col["z"]], "z");
    r.roll = parseFinite(path, n, cells[col["roll"]], "roll");
    r.pitch = parseFinite(path, n, cells[col["pitch"]], "pitch");
    r.yaw = parseFinite(path, n, cells[col["yaw"]], "yaw");
    if (has_radar) {
      r.source_radar = parseInt64(path, n, cells[col["source_radar_timestamp"]], "source_radar_timestamp");
      r.destination_radar =
          parseInt64(path, n, cells[col["destination_radar_timestamp"]], "destination_radar_timestamp");
    } else {
      r.source_radar = r.source;
      r.destination_radar = r.destination;
    }
    if (r.source <= r.destination)
      throw IoError(path, n, "source_timestamp must be later than destination_timestamp (the dataset's order)");
    if (!out.empty() && r.destination != out.back().source)
      throw IoError(path, n,
                    "row does not chain: destination_timestamp " + std::to_string(r.destination) +
                        " is not the previous row's source_timestamp " + std::to_string(out.back().source));
    out.push_back(r);
  }
  return out;
}

void writeOxfordRadarOdometry(const std::string& path, const std::vector<OxfordRelativePose>& rows) {
  std::ostringstream s;
  s.precision(17);
  s << "source_timestamp,destination_timestamp,x,y,z,roll,pitch,yaw,source_radar_timestamp,destination_radar_"
       "timestamp\n";
  for (const auto& r : rows)
    s << r.source << ',' << r.destination << ',' << r.x << ',' << r.y << ',' << r.z << ',' << r.roll << ',' << r.pitch
      << ',' << r.yaw << ',' << r.source_radar << ',' << r.destination_radar << '\n';
  writeFileAtomically(path, s.str());
}

std::vector<RadiateFrame> readRadiateFrameTimes(const std::string& path, std::vector<IoError>* skipped) {
  std::ifstream in(path);
  if (!in) throw IoError(path, "cannot open file");
  std::vector<RadiateFrame> out;
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    ++n;
    try {
      std::istringstream ss(line);
      std::string kf, f, kt, t;
      if (!(ss >> kf)) continue;
      if (kf != "Frame:" || !(ss >> f >> kt >> t) || kt != "Time:")
        throw IoError(path, n, "expected 'Frame: <n> Time: <seconds>', found '" + line + "'");
      RadiateFrame r;
      const std::int64_t frame = parseInt64(path, n, f, "frame number");
      if (frame < 0 || frame > 999999) throw IoError(path, n, "frame number " + f + " outside 0..999999");
      r.frame = static_cast<int>(frame);
      // Seconds with up to 9 decimals: split at the dot to keep microseconds exact.
      const std::size_t dot = t.find('.');
      const std::string whole = t.substr(0, dot);
      std::string frac = dot == std::string::npos ? "" : t.substr(dot + 1);
      for (char c : frac)
        if (c < '0' || c > '9') throw IoError(path, n, "cannot parse time '" + t + "'");
      frac = (frac + "000000").substr(0, 6);
      const std::int64_t seconds = parseInt64(path, n, whole, "time");
      // Microseconds must fit in 64 bits (and a negative time is no Navtech clock).
      if (seconds < 0 || seconds > std::numeric_limits<std::int64_t>::max() / 1000000 - 1)
        throw IoError(path, n, "time '" + t + "' out of range");
      r.stamp_us = seconds * 1000000 + parseInt64(path, n, frac, "time");
      if (!out.empty() && r.stamp_us <= out.back().stamp_us)
        throw IoError(
            path, n,
            std::string(r.stamp_us == out.back().stamp_us ? "duplicated frame time" : "frame times out of order") +
                " (frame " + f + ")");
      out.push_back(r);
    } catch (const IoError& e) {
      if (!skipped) throw;
      skipped->push_back(e);
    }
  }
  return out;
}

}  // namespace radar_ndt

// The fast path of the polar-scan PNG decoder. A file is taken only when every rule libpng would
// enforce on it is checked here the same way, so that the pixels are libpng's and no file libpng
// refuses is decoded: the signature, IHDR first with a valid layout, chunk names and lengths, the
// CRC of every critical chunk, contiguous IDATs, one zlib stream with a 32 KiB window that ends
// exactly with the image data (its Adler-32 checked by libdeflate), known row filters, IEND. Where
// libpng would only warn (an ancillary chunk's CRC, a stream longer than the image, a bad Adler-32)
// or might err in ways not worth repeating (huge ancillary chunks, anything not critical to the
// pixels that libpng parses), the file is handed back and libpng decides.
#include "png_fast.h"

#include <libdeflate.h>

#include <cstring>
#include <memory>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace radar_ndt {
namespace detail {
namespace {

constexpr std::uint8_t kSignature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
constexpr std::uint32_t kMaxChunkLength = 0x7fffffffu;   // PNG: lengths are at most 2^31 - 1
constexpr std::uint32_t kMaxDimension = 1000000;         // libpng's default PNG_USER_{WIDTH,HEIGHT}_MAX
constexpr std::uint32_t kMaxAncillaryLength = 1u << 16;  // well below libpng's chunk size limit
// libpng refuses a chunk longer than PNG_USER_CHUNK_MALLOC_MAX (8,000,000 in Debian's build) unless
// it is an IDAT no longer than the image plus zlib's overhead: every IDAT up to this is libpng's too.
constexpr std::uint32_t kMaxIdatLength = 8000000;

std::uint32_t readBe32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

bool isLetter(std::uint8_t c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}

struct Chunk {
  const std::uint8_t* type = nullptr;  ///< 4 bytes
  const std::uint8_t* data = nullptr;
  std::uint32_t length = 0;
  bool is(const char* name) const { return std::memcmp(type, name, 4) == 0; }
  bool critical() const { return (type[0] & 0x20) == 0; }
  bool crcMatches() const { return libdeflate_crc32(0, type, std::size_t{length} + 4) == readBe32(data + length); }
};

/// Reads the chunk at `at`; false when its header or body runs past the file or its name or
/// length is invalid.
bool chunkAt(const std::string& file, std::size_t at, Chunk& chunk) {
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(file.data());
  if (file.size() < 12 || at > file.size() - 12) return false;
  chunk.length = readBe32(bytes + at);
  chunk.type = bytes + at + 4;
  chunk.data = bytes + at + 8;
  for (int i = 0; i < 4; ++i)
    if (!isLetter(chunk.type[i])) return false;
  return chunk.length <= kMaxChunkLength && chunk.length <= file.size() - at - 12;
}

/// The IDAT bytes of the file, gathered (one zlib stream); false when the chunk sequence is one
/// this path does not take. `at` starts after IHDR.
bool gatherImageData(const std::string& file, std::size_t at, std::string& stream) {
  stream.clear();
  bool in_idat = false, idat_done = false;
  for (Chunk c; chunkAt(file, at, c); at += std::size_t{c.length} + 12) {
    if (c.is("IEND")) return c.length == 0 && c.crcMatches() && in_idat;
    if (c.is("IDAT")) {
      if (idat_done || c.length > kMaxIdatLength || !c.crcMatches()) return false;
      in_idat = true;
      stream.append(reinterpret_cast<const char*>(c.data), c.length);
      continue;
    }
    if (c.critical() || c.length > kMaxAncillaryLength) return false;  // PLTE, an unknown critical chunk
    idat_done = in_idat;
  }
  return false;  // the file ends before IEND
}

struct DecompressorDeleter {
  void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

/// Inflates the zlib stream into exactly `size` bytes: false unless the stream is well formed, has
/// a 32 KiB window (the one libpng and libdeflate read alike), fills `out` and ends with the data.
bool inflateExactly(const std::string& stream, std::uint8_t* out, std::size_t size) {
  if (stream.size() < 2 || (static_cast<std::uint8_t>(stream[0]) >> 4) != 7) return false;
  thread_local std::unique_ptr<libdeflate_decompressor, DecompressorDeleter> decompressor(
      libdeflate_alloc_decompressor());
  if (!decompressor) return false;
  std::size_t in_used = 0, out_used = 0;
  const libdeflate_result r =
      libdeflate_zlib_decompress_ex(decompressor.get(), stream.data(), stream.size(), out, size, &in_used, &out_used);
  return r == LIBDEFLATE_SUCCESS && in_used == stream.size() && out_used == size;
}

/// Sub's running sum, out[x] = filtered[x] + out[x - 1] (mod 256), 16 bytes at a time where SSE2
/// is there: each block's prefix sum in four shifted adds, plus the last byte of the block before
/// (radar scans are stored with Sub on every row, so this is most of the unfiltering).
void unfilterSub(const std::uint8_t* filtered, std::uint8_t* out, std::size_t width) {
  std::size_t x = 0;
  std::uint8_t left = 0;
#if defined(__SSE2__)
  __m128i carry = _mm_setzero_si128();  // the previous block's last byte in every lane
  for (; x + 16 <= width; x += 16) {
    __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(filtered + x));
    v = _mm_add_epi8(v, _mm_slli_si128(v, 1));
    v = _mm_add_epi8(v, _mm_slli_si128(v, 2));
    v = _mm_add_epi8(v, _mm_slli_si128(v, 4));
    v = _mm_add_epi8(v, _mm_slli_si128(v, 8));
    v = _mm_add_epi8(v, carry);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + x), v);
    const __m128i high = _mm_unpackhi_epi8(v, v);
    carry = _mm_shuffle_epi32(_mm_unpackhi_epi16(high, high), 0xff);
  }
  if (x > 0) left = out[x - 1];
#endif
  for (; x < width; ++x) left = out[x] = static_cast<std::uint8_t>(filtered[x] + left);
}

}  // namespace

bool unfilterRow(int type, const std::uint8_t* filtered, const std::uint8_t* previous, std::uint8_t* out,
                 std::size_t width) {
  switch (type) {
    case 0:  // None
      std::memcpy(out, filtered, width);
      return true;
    case 1:  // Sub: the byte to the left
      unfilterSub(filtered, out, width);
      return true;
    case 2:  // Up: the byte above
      if (!previous) {
        std::memcpy(out, filtered, width);
        return true;
      }
      for (std::size_t x = 0; x < width; ++x) out[x] = static_cast<std::uint8_t>(filtered[x] + previous[x]);
      return true;
    case 3: {  // Average of left and above, rounded down
      unsigned left = 0;
      for (std::size_t x = 0; x < width; ++x) {
        const unsigned up = previous ? previous[x] : 0u;
        left = out[x] = static_cast<std::uint8_t>(filtered[x] + ((left + up) >> 1));
      }
      return true;
    }
    case 4: {  // Paeth: left, above or upper left, whichever is nearest to left + above - upper left
      int left = 0, upper_left = 0;
      for (std::size_t x = 0; x < width; ++x) {
        const int up = previous ? previous[x] : 0;
        const int p = left + up - upper_left;
        const int pa = p > left ? p - left : left - p;
        const int pb = p > up ? p - up : up - p;
        const int pc = p > upper_left ? p - upper_left : upper_left - p;
        const int predictor = (pa <= pb && pa <= pc) ? left : (pb <= pc ? up : upper_left);
        left = out[x] = static_cast<std::uint8_t>(filtered[x] + predictor);
        upper_left = up;
      }
      return true;
    }
    default: return false;
  }
}

bool decodeCanonicalGrayPng(const std::string& data, std::size_t max_pixels, std::size_t max_inflation, int& width,
                            int& height, std::vector<std::uint8_t>& pixels) {
  if (data.size() < 8 || std::memcmp(data.data(), kSignature, 8) != 0) return false;
  Chunk ihdr;
  if (!chunkAt(data, 8, ihdr) || !ihdr.is("IHDR") || ihdr.length != 13 || !ihdr.crcMatches()) return false;
  const std::uint32_t w = readBe32(ihdr.data), h = readBe32(ihdr.data + 4);
  const std::uint8_t* layout = ihdr.data + 8;  // bit depth, colour type, compression, filter, interlace
  if (w == 0 || h == 0 || w > kMaxDimension || h > kMaxDimension) return false;
  if (layout[0] != 8 || layout[1] != 0 || layout[2] != 0 || layout[3] != 0 || layout[4] != 0) return false;
  const std::size_t count = std::size_t{w} * h;
  if (count > max_pixels || count / max_inflation > data.size()) return false;
  const std::size_t row_bytes = std::size_t{w} + 1;  // the filter-type byte, then the row
  thread_local std::string stream;
  thread_local std::vector<std::uint8_t> filtered;
  if (!gatherImageData(data, 8 + 12 + 13, stream)) return false;
  filtered.resize(row_bytes * h);
  if (!inflateExactly(stream, filtered.data(), filtered.size())) return false;
  pixels.resize(count);
  for (std::uint32_t r = 0; r < h; ++r) {
    const std::uint8_t* in = filtered.data() + r * row_bytes;
    std::uint8_t* out = pixels.data() + std::size_t{r} * w;
    if (!unfilterRow(in[0], in + 1, r > 0 ? out - w : nullptr, out, w)) return false;
  }
  width = static_cast<int>(w);
  height = static_cast<int>(h);
  return true;
}

}  // namespace detail
}  // namespace radar_ndt

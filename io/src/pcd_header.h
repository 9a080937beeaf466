#pragma once
// Internal to RadarNDT::io: one PCD v0.7 header parser for every PCD reader here, checked against
// the file size before any point storage is allocated (PCL's own reader allocates what a header
// claims, and crashes on some non-PCD files).

#include <cstdint>
#include <string>
#include <vector>

namespace radar_ndt {
namespace detail {

struct PcdField {
  std::string name;
  std::size_t size = 4;    ///< bytes per element: 1, 2, 4 or 8
  char type = 'F';         ///< 'F' float, 'I' signed, 'U' unsigned
  std::size_t count = 1;   ///< elements per point
  std::size_t offset = 0;  ///< byte offset inside one packed point (binary layout)
};

enum class PcdData { Ascii, Binary, BinaryCompressed };

struct PcdHeader {
  std::vector<PcdField> fields;
  std::size_t width = 0, height = 0, points = 0;
  std::size_t point_bytes = 0;  ///< sum of size × count
  PcdData data = PcdData::Binary;
  std::uintmax_t data_offset = 0;  ///< first byte after the DATA line
  std::uintmax_t file_size = 0;
  /// Index of the field called `name`, or -1.
  int find(const std::string& name) const;
};

/// Parses and checks the header of `path`. Binary: the file must hold points × point_bytes bytes
/// after the header. binary_compressed: the two size words must be consistent with the header and
/// the file. ascii: the declared points must not exceed the file's bytes. Throws IoError.
PcdHeader readPcdHeader(const std::string& path);

/// Decompresses LZF (liblzf's format, as PCL's binary_compressed uses) from `in` into exactly
/// `out_size` bytes. Returns false on malformed input instead of reading or writing out of bounds.
bool lzfDecompress(const unsigned char* in, std::size_t in_size, unsigned char* out, std::size_t out_size);

/// Reads one value of field `f`'s type and size stored at `p`, as a double.
double readPcdScalar(const unsigned char* p, const PcdField& f);

/// The values of the named fields (the first element of each) of every point of `path`, whose
/// header is `h`, as doubles: `result[i * names.size() + c]`, NaN where the file has no field
/// names[c]. ascii, binary and binary_compressed. Throws IoError naming the file for truncated or
/// corrupt data or an ascii line with the wrong number of values.
std::vector<double> readPcdColumns(const std::string& path, const PcdHeader& h, const std::vector<std::string>& names);

/// `v` is finite and within float's range (converting it to float is defined and finite).
bool finiteAsFloat(double v);

}  // namespace detail
}  // namespace radar_ndt

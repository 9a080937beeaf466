#include "pcd_header.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "radar_ndt/io/io_error.h"

namespace radar_ndt {
namespace detail {

int PcdHeader::find(const std::string& name) const {
  for (std::size_t i = 0; i < fields.size(); ++i)
    if (fields[i].name == name) return static_cast<int>(i);
  return -1;
}

namespace {

/// What the header lines before DATA declared.
struct DeclaredFields {
  std::vector<std::size_t> sizes, counts;
  std::vector<char> types;
  std::vector<std::string> names;
  bool have_points = false, have_width = false;
};

/// One header line's key and values into `d` and `h`; true at the DATA line.
bool readHeaderLine(const std::string& path, std::size_t line_no, const std::string& line, DeclaredFields& d,
                    PcdHeader& h, std::vector<std::string>& values) {
  std::istringstream ls(line);
  std::string key;
  ls >> key;
  values.clear();
  for (std::string v; ls >> v;) values.push_back(v);
  auto number = [&](const std::string& v) -> std::size_t {
    if (v.empty() || v.find_first_not_of("0123456789") != std::string::npos || v.size() > 12)
      throw IoError(path, line_no, "bad number '" + v.substr(0, 20) + "' in " + key);
    return static_cast<std::size_t>(std::stoull(v));
  };
  if (key == "VERSION" || key == "VIEWPOINT") {
  } else if (key == "FIELDS") {
    d.names = values;
  } else if (key == "SIZE") {
    for (const auto& v : values) d.sizes.push_back(number(v));
  } else if (key == "TYPE") {
    for (const auto& v : values) {
      if (v != "F" && v != "I" && v != "U") throw IoError(path, line_no, "unknown TYPE '" + v.substr(0, 20) + "'");
      d.types.push_back(v[0]);
    }
  } else if (key == "COUNT") {
    for (const auto& v : values) d.counts.push_back(number(v));
  } else if (key == "WIDTH" && values.size() == 1) {
    h.width = number(values[0]);
    d.have_width = true;
  } else if (key == "HEIGHT" && values.size() == 1) {
    h.height = number(values[0]);
  } else if (key == "POINTS" && values.size() == 1) {
    h.points = number(values[0]);
    d.have_points = true;
  } else if (key == "DATA" && values.size() == 1) {
    return true;
  } else {
    throw IoError(path, line_no, "unexpected header line '" + line.substr(0, 40) + "': not a PCD file");
  }
  return false;
}

/// A declared list of `what` has one entry per field.
void requireOnePerField(const std::string& path, std::size_t line_no, const char* what, std::size_t entries,
                        std::size_t n) {
  if (entries != n)
    throw IoError(
        path, line_no,
        std::string(what) + " has " + std::to_string(entries) + " entries for " + std::to_string(n) + " fields");
}

/// At DATA: the fields with their offsets, the point size and count, checked against each other.
void setFields(const std::string& path, std::size_t line_no, DeclaredFields& d, PcdHeader& h) {
  const std::size_t n = d.names.size();
  if (n == 0) throw IoError(path, line_no, "no FIELDS before DATA");
  requireOnePerField(path, line_no, "SIZE", d.sizes.size(), n);
  if (d.types.empty()) d.types.assign(n, 'F');
  requireOnePerField(path, line_no, "TYPE", d.types.size(), n);
  if (d.counts.empty()) d.counts.assign(n, 1);
  requireOnePerField(path, line_no, "COUNT", d.counts.size(), n);
  for (std::size_t i = 0; i < n; ++i) {
    if (d.sizes[i] != 1 && d.sizes[i] != 2 && d.sizes[i] != 4 && d.sizes[i] != 8)
      throw IoError(path, line_no,
                    "field '" + d.names[i] + "' has size " + std::to_string(d.sizes[i]) + ", not 1, 2, 4 or 8");
    if (d.types[i] == 'F' && d.sizes[i] != 4 && d.sizes[i] != 8)
      throw IoError(path, line_no, "float field '" + d.names[i] + "' has size " + std::to_string(d.sizes[i]));
    if (d.counts[i] == 0 || d.counts[i] > 1000000)
      throw IoError(path, line_no, "field '" + d.names[i] + "' has COUNT " + std::to_string(d.counts[i]));
    h.fields.push_back({d.names[i], d.sizes[i], d.types[i], d.counts[i], h.point_bytes});
    h.point_bytes += d.sizes[i] * d.counts[i];
  }
  if (!d.have_width) throw IoError(path, line_no, "no WIDTH line in the header");
  if (h.height == 0 && h.width > 0) throw IoError(path, line_no, "HEIGHT 0 with WIDTH " + std::to_string(h.width));
  if (!d.have_points) h.points = h.width * h.height;
  if (h.width * h.height != h.points)
    throw IoError(
        path, line_no,
        "WIDTH x HEIGHT (" + std::to_string(h.width * h.height) + ") != POINTS (" + std::to_string(h.points) + ")");
}

/// binary_compressed: its two size words agree with the header and the file holds the data.
void checkCompressedSize(const std::string& path, std::ifstream& in, const PcdHeader& h, std::uintmax_t available) {
  if (h.points == 0) return;
  unsigned char words[8];
  if (available < 8 || !in.read(reinterpret_cast<char*>(words), 8))
    throw IoError(path, "binary_compressed data without its two size words (truncated?)");
  std::uint32_t compressed = 0, uncompressed = 0;
  for (int b = 3; b >= 0; --b) {  // little-endian, as PCL writes them
    compressed = (compressed << 8) | words[b];
    uncompressed = (uncompressed << 8) | words[4 + b];
  }
  if (static_cast<std::uintmax_t>(uncompressed) != static_cast<std::uintmax_t>(h.points) * h.point_bytes)
    throw IoError(path, "binary_compressed size word says " + std::to_string(uncompressed) +
                            " bytes, the header needs " + std::to_string(h.points * h.point_bytes));
  if (compressed > available - 8)
    throw IoError(path, "binary_compressed data of " + std::to_string(compressed) + " bytes, but the file holds " +
                            std::to_string(available - 8) + " (truncated?)");
}

/// The data format DATA names, checked against what the file holds after the header.
void setData(const std::string& path, std::ifstream& in, std::size_t line_no, const std::string& format, PcdHeader& h) {
  if (!in.good()) throw IoError(path, line_no, "header ends without data");
  h.data_offset = static_cast<std::uintmax_t>(in.tellg());
  const std::uintmax_t available = h.file_size - std::min(h.file_size, h.data_offset);
  if (format == "binary") {
    h.data = PcdData::Binary;
    const std::uintmax_t need = static_cast<std::uintmax_t>(h.points) * h.point_bytes;
    if (available < need)
      throw IoError(path, "header declares " + std::to_string(h.points) + " points of " +
                              std::to_string(h.point_bytes) + " bytes, but the file holds only " +
                              std::to_string(available) + " data bytes (truncated?)");
  } else if (format == "ascii") {
    h.data = PcdData::Ascii;
    if (h.points > available)
      throw IoError(path, "header declares " + std::to_string(h.points) + " points, more than the file has bytes");
  } else if (format == "binary_compressed") {
    h.data = PcdData::BinaryCompressed;
    checkCompressedSize(path, in, h, available);
  } else {
    throw IoError(path, line_no, "unknown DATA format '" + format.substr(0, 20) + "'");
  }
}

}  // namespace

PcdHeader readPcdHeader(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw IoError(path, "no such file");
  PcdHeader h;
  h.file_size = std::filesystem::file_size(path, ec);
  if (ec) throw IoError(path, "cannot open file for reading");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, "cannot open file for reading");
  if (h.file_size == 0) throw IoError(path, "empty file: not a PCD file");
  DeclaredFields declared;
  std::vector<std::string> values;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line_no > 64) throw IoError(path, "no DATA line in the first 64 header lines: not a PCD file");
    if (line.size() > 4096) throw IoError(path, line_no, "header line longer than 4096 bytes: not a PCD file");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    if (!readHeaderLine(path, line_no, line, declared, h, values)) continue;
    setFields(path, line_no, declared, h);
    setData(path, in, line_no, values[0], h);
    return h;
  }
  throw IoError(path, "no DATA line: not a PCD file (or a truncated header)");
}

bool lzfDecompress(const unsigned char* in, std::size_t in_size, unsigned char* out, std::size_t out_size) {
  std::size_t ip = 0, op = 0;
  while (ip < in_size) {
    std::size_t ctrl = in[ip++];
    if (ctrl < 32) {  // literal run of ctrl + 1 bytes
      const std::size_t len = ctrl + 1;
      if (ip + len > in_size || op + len > out_size) return false;
      std::memcpy(out + op, in + ip, len);
      ip += len;
      op += len;
    } else {  // back reference
      std::size_t len = ctrl >> 5;
      if (len == 7) {
        if (ip >= in_size) return false;
        len += in[ip++];
      }
      if (ip >= in_size) return false;
      const std::size_t back = ((ctrl & 0x1f) << 8) + in[ip++] + 1;
      len += 2;
      if (back > op || op + len > out_size) return false;
      for (std::size_t k = 0; k < len; ++k, ++op) out[op] = out[op - back];  // may overlap
    }
  }
  return op == out_size;
}

double readPcdScalar(const unsigned char* p, const PcdField& f) {
  switch (f.type) {
    case 'F':
      if (f.size == 4) {
        float v;
        std::memcpy(&v, p, 4);
        return v;
      } else {
        double v;
        std::memcpy(&v, p, 8);
        return v;
      }
    case 'I':
      switch (f.size) {
        case 1: {
          std::int8_t v;
          std::memcpy(&v, p, 1);
          return v;
        }
        case 2: {
          std::int16_t v;
          std::memcpy(&v, p, 2);
          return v;
        }
        case 4: {
          std::int32_t v;
          std::memcpy(&v, p, 4);
          return v;
        }
        default: {
          std::int64_t v;
          std::memcpy(&v, p, 8);
          return static_cast<double>(v);
        }
      }
    default:
      switch (f.size) {
        case 1: return p[0];
        case 2: {
          std::uint16_t v;
          std::memcpy(&v, p, 2);
          return v;
        }
        case 4: {
          std::uint32_t v;
          std::memcpy(&v, p, 4);
          return v;
        }
        default: {
          std::uint64_t v;
          std::memcpy(&v, p, 8);
          return static_cast<double>(v);
        }
      }
  }
}

bool finiteAsFloat(double v) {
  return std::isfinite(v) && std::abs(v) <= std::numeric_limits<float>::max();
}

namespace {

/// ASCII data: each line's values, the wanted columns (`col`: the field index, −1 for none) into
/// `table`, n lines of the declared value count.
void readAsciiColumns(const std::string& path, std::ifstream& in, const PcdHeader& h, const std::vector<int>& col,
                      std::vector<double>& table) {
  const std::size_t n = h.points, k = col.size();
  // Position of each wanted column's first value on a line, and the values a line must have.
  std::size_t expected = 0;
  std::vector<std::size_t> pos(k, 0);
  for (std::size_t f = 0; f < h.fields.size(); ++f) {
    for (std::size_t c = 0; c < k; ++c)
      if (col[c] == static_cast<int>(f)) pos[c] = expected;
    expected += h.fields[f].count;
  }
  std::string line;
  std::size_t i = 0, line_number = 0;
  std::vector<double> values;
  while (i < n && std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    values.clear();
    const char* s = line.c_str();
    char* end = nullptr;
    for (;;) {
      while (*s == ' ' || *s == '\t') ++s;
      if (!*s) break;
      const double v = std::strtod(s, &end);
      if (end == s)
        throw IoError(path, "data line " + std::to_string(line_number) + ": unparsable value '" +
                                std::string(s).substr(0, 20) + "'");
      values.push_back(v);
      s = end;
    }
    if (values.size() != expected)
      throw IoError(path, "data line " + std::to_string(line_number) + ": " + std::to_string(values.size()) +
                              " values, the header declares " + std::to_string(expected));
    for (std::size_t c = 0; c < k; ++c)
      if (col[c] >= 0) table[i * k + c] = values[pos[c]];
    ++i;
  }
  if (i < n) throw IoError(path, "truncated: " + std::to_string(i) + " of " + std::to_string(n) + " declared points");
}

/// Binary data, decompressed when it is binary_compressed; true when it is stored field after field
/// (binary_compressed's structure of arrays).
bool readBinaryData(const std::string& path, std::ifstream& in, const PcdHeader& h, std::vector<unsigned char>& data) {
  if (h.data == PcdData::Binary) {
    if (!in.read(reinterpret_cast<char*>(data.data()), static_cast<std::streamsize>(data.size())))
      throw IoError(path, "truncated binary data");
    return false;
  }
  unsigned char words[8];
  if (!in.read(reinterpret_cast<char*>(words), 8)) throw IoError(path, "truncated binary_compressed data");
  std::uint32_t compressed = 0;
  for (int b = 3; b >= 0; --b) compressed = (compressed << 8) | words[b];
  std::vector<unsigned char> packed(compressed);
  if (!in.read(reinterpret_cast<char*>(packed.data()), static_cast<std::streamsize>(packed.size())))
    throw IoError(path, "truncated binary_compressed data");
  if (!lzfDecompress(packed.data(), packed.size(), data.data(), data.size()))
    throw IoError(path, "corrupt binary_compressed data (LZF stream does not decode to the declared size)");
  return true;
}

}  // namespace

std::vector<double> readPcdColumns(const std::string& path, const PcdHeader& h, const std::vector<std::string>& names) {
  const std::size_t n = h.points, k = names.size();
  std::vector<int> col(k);
  for (std::size_t c = 0; c < k; ++c) col[c] = h.find(names[c]);
  std::vector<double> table(n * k, std::numeric_limits<double>::quiet_NaN());
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, "cannot open file for reading");
  in.seekg(static_cast<std::streamoff>(h.data_offset));
  if (h.data == PcdData::Ascii) {
    readAsciiColumns(path, in, h, col, table);
    return table;
  }
  if (n == 0) return table;
  std::vector<unsigned char> data(n * h.point_bytes);
  const bool soa = readBinaryData(path, in, h, data);
  for (std::size_t c = 0; c < k; ++c) {
    if (col[c] < 0) continue;
    const PcdField& f = h.fields[static_cast<std::size_t>(col[c])];
    // Where element 0 of this field of point i starts, in either layout.
    const std::size_t start = soa ? n * f.offset : f.offset;
    const std::size_t stride = soa ? f.size * f.count : h.point_bytes;
    for (std::size_t i = 0; i < n; ++i) table[i * k + c] = readPcdScalar(data.data() + start + i * stride, f);
  }
  return table;
}

}  // namespace detail
}  // namespace radar_ndt

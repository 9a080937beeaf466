#define PCL_NO_PRECOMPILE
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <pcl/io/pcd_io.h>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/pcd.h"

namespace radar_ndt {

namespace {

/// Checks a PCD header against the PCD v0.7 layout and, for binary data, against the file size,
/// before PCL's reader sees the file (it crashes on some malformed files and allocates what a
/// header claims before checking it).
void validatePcdHeader(const std::string& path) {
  std::error_code ec;
  const auto file_size = std::filesystem::file_size(path, ec);
  if (ec) throw IoError(path, "cannot open file for reading");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, "cannot open file for reading");
  std::size_t n_fields = 0, width = 0, height = 0, points = 0, point_bytes = 0;
  std::vector<std::size_t> sizes, counts;
  bool have_points = false;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line_no > 64) throw IoError(path, "no DATA line in the first 64 header lines: not a PCD file");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    std::vector<std::string> values;
    for (std::string v; ls >> v;) values.push_back(v);
    auto number = [&](const std::string& v) -> std::size_t {
      if (v.empty() || v.find_first_not_of("0123456789") != std::string::npos || v.size() > 12)
        throw IoError(path, line_no, "bad number '" + v + "' in " + key);
      return static_cast<std::size_t>(std::stoull(v));
    };
    if (key == "VERSION") {
    } else if (key == "FIELDS") {
      n_fields = values.size();
    } else if (key == "SIZE") {
      for (const auto& v : values) sizes.push_back(number(v));
    } else if (key == "TYPE") {
      for (const auto& v : values)
        if (v != "F" && v != "I" && v != "U") throw IoError(path, line_no, "unknown TYPE '" + v + "'");
    } else if (key == "COUNT") {
      for (const auto& v : values) counts.push_back(number(v));
    } else if (key == "WIDTH" && values.size() == 1) {
      width = number(values[0]);
    } else if (key == "HEIGHT" && values.size() == 1) {
      height = number(values[0]);
    } else if (key == "VIEWPOINT") {
    } else if (key == "POINTS" && values.size() == 1) {
      points = number(values[0]);
      have_points = true;
    } else if (key == "DATA" && values.size() == 1) {
      if (n_fields == 0) throw IoError(path, line_no, "no FIELDS before DATA");
      if (sizes.size() != n_fields) throw IoError(path, line_no, "SIZE has " + std::to_string(sizes.size()) + " entries for " + std::to_string(n_fields) + " fields");
      if (counts.empty()) counts.assign(n_fields, 1);
      if (counts.size() != n_fields) throw IoError(path, line_no, "COUNT does not match FIELDS");
      for (std::size_t i = 0; i < n_fields; ++i) {
        if (sizes[i] != 1 && sizes[i] != 2 && sizes[i] != 4 && sizes[i] != 8)
          throw IoError(path, line_no, "field size " + std::to_string(sizes[i]) + " is not 1, 2, 4 or 8");
        point_bytes += sizes[i] * counts[i];
      }
      if (!have_points) points = width * height;
      if (width * height != points)
        throw IoError(path, line_no, "WIDTH x HEIGHT (" + std::to_string(width * height) + ") != POINTS (" + std::to_string(points) + ")");
      const auto data_start = static_cast<std::uintmax_t>(in.tellg());
      if (values[0] == "binary") {
        const std::uintmax_t need = static_cast<std::uintmax_t>(points) * point_bytes;
        if (file_size < data_start || file_size - data_start < need)
          throw IoError(path, "header declares " + std::to_string(points) + " points of " + std::to_string(point_bytes) +
                                  " bytes, but the file holds only " + std::to_string(file_size - std::min(file_size, data_start)) + " data bytes");
      } else if (values[0] == "ascii") {
        if (points > file_size) throw IoError(path, "header declares more points than the file has bytes");
      } else if (values[0] != "binary_compressed") {
        throw IoError(path, line_no, "unknown DATA format '" + values[0] + "'");
      }
      return;
    } else {
      throw IoError(path, line_no, "unexpected header line '" + line.substr(0, 40) + "': not a PCD file");
    }
  }
  throw IoError(path, "no DATA line: not a PCD file (or a truncated header)");
}

}  // namespace

pcl::PointCloud<PointRadar> loadPointRadarPcd(const std::string& path) {
  validatePcdHeader(path);
  pcl::PCLPointCloud2 blob;
  pcl::PCDReader reader;
  if (reader.read(path, blob) != 0) throw IoError(path, "not a readable PCD file (see the PCL error above)");
  pcl::PointCloud<PointRadar> cloud;
  if (static_cast<std::size_t>(blob.width) * blob.height == 0) {  // a valid, empty scan
    cloud.header = blob.header;
    return cloud;
  }
  pcl::MsgFieldMap field_map;
  pcl::createMapping<PointRadar>(blob.fields, field_map);
  // Fields missing from the file keep PointRadar's defaults: start from default points and let
  // fromPCLPointCloud2 overwrite what the file has.
  cloud.resize(static_cast<std::size_t>(blob.width) * blob.height);
  pcl::fromPCLPointCloud2(blob, cloud, field_map);
  return cloud;
}

void savePointRadarPcd(const std::string& path, const pcl::PointCloud<PointRadar>& cloud, bool binary) {
  const std::string tmp = path + ".tmp." + std::to_string(static_cast<long>(::getpid()));
  pcl::PCDWriter writer;
  if (writer.write(tmp, cloud, binary) != 0) {
    std::remove(tmp.c_str());
    throw IoError(path, "cannot write PCD file");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw IoError(path, "cannot rename the temporary file into place");
  }
}

}  // namespace radar_ndt

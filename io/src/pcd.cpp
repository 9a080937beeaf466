#define PCL_NO_PRECOMPILE
#include <unistd.h>

#include <cstdio>

#include <pcl/io/pcd_io.h>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/pcd.h"
#include "pcd_header.h"

namespace radar_ndt {

pcl::PointCloud<PointRadar> loadPointRadarPcd(const std::string& path) {
  detail::readPcdHeader(path);  // checks the header against the file before PCL reads it
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

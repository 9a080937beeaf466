#include "radar_ndt/ros/point_cloud2.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace radar_ndt {
namespace ros1 {

namespace {

std::size_t sizeOf(std::uint8_t datatype) {
  using F = sensor_msgs::PointField;
  switch (datatype) {
    case F::INT8:
    case F::UINT8: return 1;
    case F::INT16:
    case F::UINT16: return 2;
    case F::INT32:
    case F::UINT32:
    case F::FLOAT32: return 4;
    case F::FLOAT64: return 8;
    default: return 0;
  }
}

/// The value at `p` (`size` bytes, swapped first when the message's byte order is not this machine's).
double valueAt(const std::uint8_t* p, std::uint8_t datatype, bool swap) {
  std::uint8_t b[8];
  const std::size_t n = sizeOf(datatype);
  for (std::size_t i = 0; i < n; ++i) b[i] = swap ? p[n - 1 - i] : p[i];
  using F = sensor_msgs::PointField;
  switch (datatype) {
    case F::INT8: {
      std::int8_t v;
      std::memcpy(&v, b, 1);
      return v;
    }
    case F::UINT8: return b[0];
    case F::INT16: {
      std::int16_t v;
      std::memcpy(&v, b, 2);
      return v;
    }
    case F::UINT16: {
      std::uint16_t v;
      std::memcpy(&v, b, 2);
      return v;
    }
    case F::INT32: {
      std::int32_t v;
      std::memcpy(&v, b, 4);
      return v;
    }
    case F::UINT32: {
      std::uint32_t v;
      std::memcpy(&v, b, 4);
      return v;
    }
    case F::FLOAT32: {
      float v;
      std::memcpy(&v, b, 4);
      return v;
    }
    default: {
      double v;
      std::memcpy(&v, b, 8);
      return v;
    }
  }
}

bool littleEndianMachine() {
  const std::uint16_t one = 1;
  std::uint8_t first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

}  // namespace

std::string fieldNames(const sensor_msgs::PointCloud2& cloud) {
  std::string names;
  for (const auto& f : cloud.fields) names += (names.empty() ? "" : ", ") + f.name;
  return names.empty() ? "none" : names;
}

CloudColumns readCloudColumns(const sensor_msgs::PointCloud2& cloud, const std::vector<std::string>& names) {
  const std::uint64_t points = static_cast<std::uint64_t>(cloud.width) * cloud.height;
  if (points > 0 && cloud.point_step == 0) throw std::invalid_argument("point_step is 0");
  if (cloud.row_step < static_cast<std::uint64_t>(cloud.width) * cloud.point_step)
    throw std::invalid_argument("row_step " + std::to_string(cloud.row_step) + " is less than width x point_step (" +
                                std::to_string(cloud.width) + " x " + std::to_string(cloud.point_step) + ")");
  if (cloud.data.size() < static_cast<std::uint64_t>(cloud.row_step) * cloud.height)
    throw std::invalid_argument("data holds " + std::to_string(cloud.data.size()) + " bytes, height x row_step is " +
                                std::to_string(static_cast<std::uint64_t>(cloud.row_step) * cloud.height) +
                                " (truncated)");
  CloudColumns out;
  out.points = static_cast<std::size_t>(points);
  const std::size_t columns = names.size();
  std::vector<const sensor_msgs::PointField*> field(columns, nullptr);
  for (std::size_t c = 0; c < columns; ++c)
    for (const auto& f : cloud.fields)
      if (f.name == names[c] && !field[c]) field[c] = &f;
  for (std::size_t c = 0; c < columns; ++c) {
    out.present.push_back(field[c] != nullptr);
    if (!field[c]) continue;
    const std::size_t size = sizeOf(field[c]->datatype);
    if (size == 0)
      throw std::invalid_argument("field '" + names[c] + "' has unknown datatype " +
                                  std::to_string(field[c]->datatype));
    if (field[c]->count == 0) throw std::invalid_argument("field '" + names[c] + "' has count 0");
    if (static_cast<std::uint64_t>(field[c]->offset) + size > cloud.point_step)
      throw std::invalid_argument("field '" + names[c] + "' (offset " + std::to_string(field[c]->offset) +
                                  ") lies beyond the point's " + std::to_string(cloud.point_step) + " bytes");
  }
  const bool swap = (cloud.is_bigendian != 0) == littleEndianMachine();
  out.table.assign(out.points * columns, std::numeric_limits<double>::quiet_NaN());
  std::size_t i = 0;
  for (std::uint32_t row = 0; row < cloud.height; ++row)
    for (std::uint32_t col = 0; col < cloud.width; ++col, ++i) {
      const std::uint8_t* point = cloud.data.data() + static_cast<std::size_t>(row) * cloud.row_step +
                                  static_cast<std::size_t>(col) * cloud.point_step;
      for (std::size_t c = 0; c < columns; ++c)
        if (field[c]) out.table[i * columns + c] = valueAt(point + field[c]->offset, field[c]->datatype, swap);
    }
  return out;
}

namespace {

template <typename T>
void put(std::uint8_t* p, double v) {
  const T x = static_cast<T>(v);
  std::memcpy(p, &x, sizeof(T));
}

}  // namespace

sensor_msgs::PointCloud2 writeCloud(const std::vector<std::string>& names, const std::vector<std::uint8_t>& types,
                                    std::size_t points, const std::function<double(std::size_t, std::size_t)>& value) {
  using F = sensor_msgs::PointField;
  sensor_msgs::PointCloud2 msg;
  std::uint32_t offset = 0;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::size_t size = sizeOf(types[k]);
    if (size == 0) throw std::invalid_argument("field '" + names[k] + "': unknown PointField datatype");
    F f;
    f.name = names[k];
    f.offset = offset;
    f.datatype = types[k];
    f.count = 1;
    msg.fields.push_back(f);
    offset += static_cast<std::uint32_t>(size);
  }
  msg.height = 1;
  msg.width = static_cast<std::uint32_t>(points);
  msg.point_step = offset;
  msg.row_step = offset * msg.width;
  msg.is_bigendian = false;
  msg.is_dense = false;
  msg.data.assign(static_cast<std::size_t>(msg.row_step), 0);
  for (std::size_t i = 0; i < points; ++i)
    for (std::size_t k = 0; k < names.size(); ++k) {
      std::uint8_t* p = msg.data.data() + i * offset + msg.fields[k].offset;
      const double v = value(i, k);
      switch (types[k]) {
        case F::FLOAT32: put<float>(p, v); break;
        case F::FLOAT64: put<double>(p, v); break;
        case F::INT8: put<std::int8_t>(p, v); break;
        case F::INT16: put<std::int16_t>(p, v); break;
        case F::INT32: put<std::int32_t>(p, v); break;
        case F::UINT8: put<std::uint8_t>(p, v); break;
        case F::UINT16: put<std::uint16_t>(p, v); break;
        default: put<std::uint32_t>(p, v); break;
      }
    }
  return msg;
}

}  // namespace ros1
}  // namespace radar_ndt

namespace radar_ndt {
namespace ros1 {

std::string fieldNames(const sensor_msgs::PointCloud& cloud) {
  std::string names = "x, y, z";
  for (const auto& c : cloud.channels) names += ", " + (c.name.empty() ? std::string("(unnamed)") : c.name);
  return names;
}

CloudColumns readCloudColumns(const sensor_msgs::PointCloud& cloud, const std::vector<std::string>& names) {
  const std::size_t n = cloud.points.size();
  for (std::size_t c = 0; c < cloud.channels.size(); ++c)
    if (cloud.channels[c].values.size() != n)
      throw std::invalid_argument("channel " + std::to_string(c) + " ('" + cloud.channels[c].name + "') has " +
                                  std::to_string(cloud.channels[c].values.size()) + " values for " + std::to_string(n) +
                                  " points");
  // Each requested name: a coordinate (-1, -2, -3), a channel's index, or absent (npos).
  constexpr std::size_t kAbsent = static_cast<std::size_t>(-1);
  std::vector<std::size_t> source(names.size(), kAbsent);
  std::vector<int> coordinate(names.size(), -1);
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string& name = names[k];
    if (name == "x" || name == "y" || name == "z") {
      coordinate[k] = name[0] - 'x';
      continue;
    }
    if (name.size() > 1 && name[0] == '#' && name.find_first_not_of("0123456789", 1) == std::string::npos) {
      // Digits past any real channel count name no channel (and would overflow stoul).
      const std::size_t index = name.size() > 10 ? kAbsent : std::stoul(name.substr(1));
      if (index < cloud.channels.size()) source[k] = index;
      continue;
    }
    for (std::size_t c = 0; c < cloud.channels.size(); ++c)
      if (cloud.channels[c].name == name) {
        source[k] = c;
        break;
      }
  }
  CloudColumns out;
  out.points = n;
  out.present.resize(names.size());
  for (std::size_t k = 0; k < names.size(); ++k) out.present[k] = coordinate[k] >= 0 || source[k] != kAbsent;
  out.table.assign(n * names.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = cloud.points[i];
    const double xyz[3] = {p.x, p.y, p.z};
    for (std::size_t k = 0; k < names.size(); ++k) {
      double& cell = out.table[i * names.size() + k];
      if (coordinate[k] >= 0)
        cell = xyz[coordinate[k]];
      else if (source[k] != kAbsent)
        cell = cloud.channels[source[k]].values[i];
    }
  }
  return out;
}

}  // namespace ros1
}  // namespace radar_ndt

#include "radar_ndt/io/boreas_imu.h"

#include <filesystem>
#include <sstream>

#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/boreas_scan.h"
#include "radar_ndt/io/io_error.h"
#include "text_lines.h"

namespace radar_ndt {
namespace {

// The released files' names, in the documented order t, wz, wy, wx, az, ay, ax.
const char* const kImuColumns[] = {"GPSTime", "angvel_z", "angvel_y", "angvel_x", "accelz", "accely", "accelx"};
constexpr std::size_t kImuColumnCount = sizeof(kImuColumns) / sizeof(kImuColumns[0]);

}  // namespace

std::vector<BoreasImuRow> readBoreasImuFile(const std::string& path) {
  const std::string text = detail::readWholeFile(path);
  std::vector<BoreasImuRow> rows;
  // Columns are found by their header names, so a file with more columns, or in another order,
  // is read too; the time and the three rates must be there.
  std::vector<int> index(kImuColumnCount, -1);
  std::size_t cells_per_row = 0;
  detail::forEachLine(text, [&](std::size_t n, const std::string& line) {
    if (detail::isBlank(line)) return true;
    const std::vector<std::string> cells = detail::splitCsv(line);
    if (cells_per_row == 0) {
      cells_per_row = cells.size();
      for (std::size_t c = 0; c < cells.size(); ++c)
        for (std::size_t k = 0; k < kImuColumnCount; ++k)
          if (cells[c] == kImuColumns[k]) index[k] = static_cast<int>(c);
      for (std::size_t k = 0; k < 4; ++k)
        if (index[k] < 0)
          throw IoError(path, n,
                        std::string("header has no column '") + kImuColumns[k] +
                            "' (a Boreas IMU file: GPSTime,angvel_z,angvel_y,angvel_x,accelz,accely,accelx)");
      return true;
    }
    if (cells.size() != cells_per_row)
      throw IoError(path, n,
                    "expected " + std::to_string(cells_per_row) + " columns, found " + std::to_string(cells.size()));
    BoreasImuRow r;
    const std::string& t = cells[static_cast<std::size_t>(index[0])];
    if (!boreasTimeMicros(t, &r.stamp_us))
      throw IoError(path, n, "GPSTime '" + t + "' is not a time (digits: µs, ns or s)");
    if (!rows.empty() && r.stamp_us <= rows.back().stamp_us)
      throw IoError(path, n, "GPSTime " + t + " does not come after the line before's");
    double v[kImuColumnCount] = {};
    for (std::size_t k = 1; k < kImuColumnCount; ++k)
      if (index[k] >= 0) v[k] = detail::parseFinite(path, n, cells[static_cast<std::size_t>(index[k])], kImuColumns[k]);
    r.angular_velocity = {v[3], v[2], v[1]};  // the file's order is z, y, x
    r.acceleration = {v[6], v[5], v[4]};
    rows.push_back(r);
    return true;
  });
  if (cells_per_row == 0) throw IoError(path, "empty: no header and no rows");
  if (rows.size() < 2) throw IoError(path, "fewer than two rows: no rate can be integrated");
  return rows;
}

std::optional<VehicleSignals> readBoreasImu(const std::string& sequence_dir) {
  const std::string path = (std::filesystem::path(sequence_dir) / "applanix" / "imu.csv").string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  VehicleSignals s;
  s.source = path;
  for (const BoreasImuRow& r : readBoreasImuFile(path)) {
    s.yaw_rate.stamps_us.push_back(r.stamp_us);
    s.yaw_rate.values.push_back(r.angular_velocity.z());  // z up: counter-clockwise positive
  }
  return s;
}

void writeBoreasImu(const std::string& path, const std::vector<BoreasImuRow>& rows) {
  std::ostringstream s;
  s.precision(17);
  for (std::size_t i = 0; i < kImuColumnCount; ++i) s << (i ? "," : "") << kImuColumns[i];
  s << '\n';
  for (const BoreasImuRow& r : rows) {
    s << r.stamp_us << "000";  // nanoseconds, as the released pose files
    for (int k = 2; k >= 0; --k) s << ',' << r.angular_velocity(k);
    for (int k = 2; k >= 0; --k) s << ',' << r.acceleration(k);
    s << '\n';
  }
  writeFileAtomically(path, s.str());
}

}  // namespace radar_ndt

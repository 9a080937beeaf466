#include "radar_ndt/io/oxford_ground_truth.h"

#include <map>
#include <sstream>

#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/io_error.h"
#include "read_file.h"
#include "text_lines.h"

namespace radar_ndt {

namespace {

// The CSV's columns by header name; the ground truth's own are required, the radar timestamps not.
struct Columns {
  std::map<std::string, std::size_t> index;
  std::size_t count = 0;
  bool has_radar = false;
};

Columns columnsOf(const std::string& path, const std::string& header_line) {
  const std::vector<std::string> header = detail::splitCsv(header_line);
  Columns c;
  c.count = header.size();
  for (std::size_t i = 0; i < header.size(); ++i) c.index[header[i]] = i;
  for (const char* need : {"source_timestamp", "destination_timestamp", "x", "y", "z", "roll", "pitch", "yaw"})
    if (!c.index.count(need)) throw IoError(path, 1, std::string("header has no column '") + need + "'");
  c.has_radar = c.index.count("source_radar_timestamp") && c.index.count("destination_radar_timestamp");
  return c;
}

OxfordRelativePose parseRow(const std::string& path, std::size_t n, const std::string& line, Columns& c) {
  const std::vector<std::string> cells = detail::splitCsv(line);
  if (cells.size() != c.count)
    throw IoError(path, n, "expected " + std::to_string(c.count) + " columns, found " + std::to_string(cells.size()));
  auto integer = [&](const char* name) { return detail::parseInt64(path, n, cells[c.index[name]], name); };
  auto number = [&](const char* name) { return detail::parseFinite(path, n, cells[c.index[name]], name); };
  OxfordRelativePose r;
  r.source = integer("source_timestamp");
  r.destination = integer("destination_timestamp");
  r.x = number("x");
  r.y = number("y");
  r.z = number("z");
  r.roll = number("roll");
  r.pitch = number("pitch");
  r.yaw = number("yaw");
  r.source_radar = c.has_radar ? integer("source_radar_timestamp") : r.source;
  r.destination_radar = c.has_radar ? integer("destination_radar_timestamp") : r.destination;
  if (r.source <= r.destination)
    throw IoError(path, n, "source_timestamp must be later than destination_timestamp (the dataset's order)");
  return r;
}

}  // namespace

std::vector<OxfordRelativePose> readOxfordRadarOdometry(const std::string& path) {
  const std::string text = detail::readWholeFile(path);
  if (text.empty()) throw IoError(path, "empty file, expected a header line");
  std::vector<OxfordRelativePose> out;
  Columns columns;
  detail::forEachLine(text, [&](std::size_t n, const std::string& line) {
    if (n == 1) {
      columns = columnsOf(path, line);
      return true;
    }
    if (detail::isBlank(line)) return true;
    const OxfordRelativePose r = parseRow(path, n, line, columns);
    if (!out.empty() && r.destination != out.back().source)
      throw IoError(path, n,
                    "row does not chain: destination_timestamp " + std::to_string(r.destination) +
                        " is not the previous row's source_timestamp " + std::to_string(out.back().source));
    out.push_back(r);
    return true;
  });
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

}  // namespace radar_ndt

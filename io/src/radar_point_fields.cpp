#include "radar_ndt/io/radar_point_fields.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "pcd_header.h"
#include "radar_ndt/io/nuscenes.h"

namespace radar_ndt {

namespace {

using detail::finiteAsFloat;

bool accepts(const std::vector<int>& allowed, double value) {
  if (allowed.empty()) return true;
  if (!std::isfinite(value)) return false;
  const int v = static_cast<int>(std::lround(value));
  return std::find(allowed.begin(), allowed.end(), v) != allowed.end();
}

/// Column positions of the named fields in RadarPointFields::columns() order.
struct Layout {
  int x = 0, y = 1, z = 2;
  int doppler_a = -1, doppler_b = -1, rcs = -1, power = -1, acc_x = -1, acc_y = -1, time = -1;
  int keep_first = 0, keep_doppler_first = 0;
  std::size_t count = 0;
  explicit Layout(const RadarPointFields& f) {
    int c = 3;
    if (f.doppler == DopplerKind::Radial) doppler_a = c++;
    if (f.doppler == DopplerKind::Components) {
      doppler_a = c++;
      doppler_b = c++;
    }
    if (!f.rcs.empty()) rcs = c++;
    if (!f.power.empty()) power = c++;
    if (f.accuracy == AccuracyKind::Ars408Rms || f.accuracy == AccuracyKind::RmsFields) {
      acc_x = c++;
      acc_y = c++;
    }
    if (!f.time.empty()) time = c++;
    keep_first = c;
    keep_doppler_first = c + static_cast<int>(f.keep.size());
    count = static_cast<std::size_t>(keep_doppler_first) + f.keep_doppler.size();
  }
};

/// Whether row `r` holds, in each listed field (its columns from `first` on), one of the field's
/// values; a field the data lacks passes.
bool passes(const std::vector<std::pair<std::string, std::vector<int>>>& lists, int first, const double* r,
            const std::vector<char>& present) {
  for (std::size_t k = 0; k < lists.size(); ++k) {
    const std::size_t c = static_cast<std::size_t>(first) + k;
    if (present[c] && !accepts(lists[k].second, r[c])) return false;
  }
  return true;
}

/// A point's standard deviations along the sensor's x and y; NaN when it has none valid.
std::pair<double, double> sigmas(const double* r, const Layout& l, const RadarPointFields& f) {
  switch (f.accuracy) {
    case AccuracyKind::Ars408Rms: {
      const double sx = std::isfinite(r[l.acc_x]) ? ars408RmsValue(static_cast<int>(std::lround(r[l.acc_x]))) : NAN;
      const double sy = std::isfinite(r[l.acc_y]) ? ars408RmsValue(static_cast<int>(std::lround(r[l.acc_y]))) : NAN;
      return {sx, sy};
    }
    case AccuracyKind::RmsFields: return {r[l.acc_x] > 0 ? r[l.acc_x] : NAN, r[l.acc_y] > 0 ? r[l.acc_y] : NAN};
    case AccuracyKind::Fixed: return {f.sigma_x, f.sigma_y};
    case AccuracyKind::Model: break;
  }
  return {NAN, NAN};
}

}  // namespace

std::vector<std::string> RadarPointFields::columns() const {
  std::vector<std::string> c{x, y, z};
  if (doppler == DopplerKind::Radial) c.push_back(radial);
  if (doppler == DopplerKind::Components) {
    c.push_back(vx);
    c.push_back(vy);
  }
  if (!rcs.empty()) c.push_back(rcs);
  if (!power.empty()) c.push_back(power);
  if (accuracy == AccuracyKind::Ars408Rms || accuracy == AccuracyKind::RmsFields) {
    c.push_back(accuracy_x);
    c.push_back(accuracy_y);
  }
  if (!time.empty()) c.push_back(time);
  for (const auto& k : keep) c.push_back(k.first);
  for (const auto& k : keep_doppler) c.push_back(k.first);
  return c;
}

std::vector<std::string> RadarPointFields::requiredColumns() const {
  std::vector<std::string> c{x, y};
  if (doppler == DopplerKind::Radial) c.push_back(radial);
  if (doppler == DopplerKind::Components) {
    c.push_back(vx);
    c.push_back(vy);
  }
  if (!time.empty()) c.push_back(time);  // described: a cloud without it is not the driver's
  return c;
}

pcl::PointCloud<PointRadar> convertRadarPoints(const std::vector<double>& table, std::size_t n,
                                               const std::vector<char>& present, const RadarPointFields& fields,
                                               std::uint16_t sensor_id, RadarPointStats* stats) {
  const Layout l(fields);
  if (present.size() != l.count || table.size() < n * l.count)
    throw std::invalid_argument("convertRadarPoints: the table does not have the fields' columns");
  RadarPointStats local;
  local.points_in_data = n;
  pcl::PointCloud<PointRadar> cloud;
  cloud.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double* r = &table[i * l.count];
    const double z = present[static_cast<std::size_t>(l.z)] ? r[l.z] : 0.0;
    const double va = l.doppler_a >= 0 ? r[l.doppler_a] : 0.0;
    const double vb = l.doppler_b >= 0 ? r[l.doppler_b] : 0.0;
    // Finite as floats too: a value beyond float's range is as unusable as Inf.
    const double t = l.time >= 0 && present[static_cast<std::size_t>(l.time)] ? r[l.time] * fields.time_scale : 0.0;
    if (!finiteAsFloat(r[l.x]) || !finiteAsFloat(r[l.y]) || !finiteAsFloat(z) || !finiteAsFloat(va) ||
        !finiteAsFloat(vb) || !finiteAsFloat(t)) {
      ++local.dropped_non_finite;
      continue;
    }
    const double range = std::sqrt(r[l.x] * r[l.x] + r[l.y] * r[l.y] + z * z);
    if (range > fields.max_range || !passes(fields.keep, l.keep_first, r, present)) {
      ++local.dropped_by_filter;
      continue;
    }
    const double power = l.power >= 0 && finiteAsFloat(r[l.power]) ? r[l.power] : 1.0;
    PointRadar p(static_cast<float>(r[l.x]), static_cast<float>(r[l.y]), static_cast<float>(z),
                 static_cast<float>(power));
    double doppler = 0.0;
    if (fields.doppler == DopplerKind::Components)
      doppler = range > 1e-6 ? (r[l.x] * va + r[l.y] * vb) / range : 0.0;
    else if (fields.doppler == DopplerKind::Radial)
      doppler = fields.radial_sign * va;
    p.doppler = finiteAsFloat(doppler) ? static_cast<float>(doppler) : 0.f;
    if (!passes(fields.keep_doppler, l.keep_doppler_first, r, present)) {
      p.doppler = std::numeric_limits<float>::quiet_NaN();
      ++local.doppler_unused;
    }
    p.rcs = l.rcs >= 0 && finiteAsFloat(r[l.rcs]) ? static_cast<float>(r[l.rcs]) : 0.f;
    p.sensor_id = sensor_id;
    p.time_offset = static_cast<float>(t);
    const auto [sx, sy] = sigmas(r, l, fields);
    if (std::isfinite(sx) && std::isfinite(sy)) {
      p.cov_xx = static_cast<float>(sx * sx);
      p.cov_yy = static_cast<float>(sy * sy);
    }
    cloud.push_back(p);
  }
  local.kept = cloud.size();
  if (stats) *stats = local;
  return cloud;
}

}  // namespace radar_ndt

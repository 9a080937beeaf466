#include "radar_ndt/pipeline/run_settings.h"

namespace radar_ndt {

const Setting* findSetting(const Settings& given, const std::string& path) {
  const Setting* found = nullptr;
  for (const Setting& s : given)
    if (s.path == path) found = &s;
  return found;
}

namespace {

/// The fields beside `path` (those under the same struct), for a message about a name that is none.
template <typename R>
std::string nearby(const std::string& path) {
  const std::size_t dot = path.rfind('.');
  const std::string parent = dot == std::string::npos ? "" : path.substr(0, dot + 1);
  std::string out;
  for (const auto& e : fieldEntries<R>())
    if (e.path.compare(0, parent.size(), parent) == 0 && e.path.find('.', parent.size()) == std::string::npos)
      out += (out.empty() ? "" : ", ") + e.path.substr(parent.size());
  return out.empty() ? ""
                     : " (" + (parent.empty() ? std::string("its") : parent.substr(0, parent.size() - 1) + "'s") +
                           " fields: " + out + ")";
}

/// Sets `s` on `o` (R's table), or refuses it naming the pipeline or layout it belongs to.
template <typename R, typename Other>
void apply(R& o, const Setting& s, const char* pipeline, const char* other_pipeline, const std::string& layout) {
  const FieldEntry<R>* e = findFieldEntry<R>(s.path);
  if (!e) {
    if (findFieldEntry<Other>(s.path))
      throw SettingError(SettingError::Why::OtherPipeline, s.spelled() + ": a setting of the " + other_pipeline +
                                                               " pipeline; this run is the " + pipeline + " one");
    throw SettingError(SettingError::Why::NoSuchSetting, s.spelled() + ": no such setting of the " +
                                                             std::string(pipeline) + " pipeline" + nearby<R>(s.path));
  }
  if (!e->scope.empty() && e->scope != layout)
    throw SettingError(SettingError::Why::NotThisLayout,
                       s.spelled() + ": applies to " + e->scope + " scans alone; this run reads " + layout);
  try {
    e->set(o, s.value, s.spelled());
  } catch (const FieldValueError& err) {
    throw SettingError(err.wrongType() ? SettingError::Why::Type : SettingError::Why::Value, err.what());
  }
}

}  // namespace

AutomotiveRunOptions automotiveRunOptions(const Settings& given, const AutomotiveRunOptions& defaults) {
  AutomotiveRunOptions o = defaults;
  // The method first, with what it needs; a given setting then overrides and validate() refuses
  // what contradicts the method.
  if (const Setting* m = findSetting(given, "matcher.method"))
    apply<AutomotiveRunOptions, ScanningRunOptions>(o, *m, "automotive", "scanning", "");
  o = withMethod(o, o.matcher.method);
  // The paper's scheme is submap to submap, not fused (AutomotiveOdometryOptions::paper).
  if (const Setting* mode = findSetting(given, "odometry.mode")) {
    apply<AutomotiveRunOptions, ScanningRunOptions>(o, *mode, "automotive", "scanning", "");
    if (o.odometry.mode == AutomotiveMatchMode::SubmapToSubmap) o.odometry.fuse_doppler = false;
  }
  for (const Setting& s : given) apply<AutomotiveRunOptions, ScanningRunOptions>(o, s, "automotive", "scanning", "");
  o.validate();
  return o;
}

ScanningRunOptions scanningRunOptions(const Settings& given, const std::string& layout,
                                      const ScanningRunOptions& defaults) {
  ScanningRunOptions o = defaults;
  for (const Setting& s : given)
    apply<ScanningRunOptions, AutomotiveRunOptions>(o, s, "scanning", "automotive", layout);
  o.validate();
  return o;
}

InertialRunOptions inertialRunOptions(const Settings& given, const InertialRunOptions& defaults) {
  InertialRunOptions o = defaults;
  for (const Setting& s : given) {
    apply<InertialRunOptions, AutomotiveRunOptions>(o, s, "6-DoF", "automotive", "");
    if (s.path.compare(0, 9, "accuracy.") == 0) o.radar_accuracy.clear();  // a given accuracy is every radar's
  }
  o.validate();
  return o;
}

std::string settingsText(const Settings& given) {
  std::string out;
  for (const Setting& s : given) out += (out.empty() ? "" : ", ") + s.path + " = " + s.value.str();
  return out;
}

}  // namespace radar_ndt

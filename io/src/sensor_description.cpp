#include "radar_ndt/io/sensor_description.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "radar_ndt/io/io_error.h"
#include "read_file.h"

#ifndef RADAR_NDT_SENSOR_PRESETS_BUILD
#define RADAR_NDT_SENSOR_PRESETS_BUILD ""
#endif
#ifndef RADAR_NDT_SENSOR_PRESETS_INSTALL
#define RADAR_NDT_SENSOR_PRESETS_INSTALL ""
#endif

namespace radar_ndt {

namespace fs = std::filesystem;

Eigen::Isometry3d MountingDescription::transform() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() << x, y, z;
  return T;
}

namespace {

/// A node with its key path, so every error names the file, the key and the line.
class Node {
 public:
  Node(YAML::Node node, std::string key, const std::string* source)
      : node_(std::move(node)), key_(std::move(key)), source_(source) {}

  [[noreturn]] void fail(const std::string& problem) const {
    std::ostringstream msg;
    msg << (key_.empty() ? "the file" : key_) << ": " << problem;
    const YAML::Mark mark = node_.Mark();
    if (mark.line >= 0) throw IoError(*source_, static_cast<std::size_t>(mark.line) + 1, msg.str());
    throw IoError(*source_, msg.str());
  }
  bool isMap() const { return node_.IsMap(); }
  bool isSequence() const { return node_.IsSequence(); }
  bool isScalar() const { return node_.IsScalar(); }
  std::size_t size() const { return node_.size(); }

  /// The child `name`, or an undefined node when absent.
  std::optional<Node> child(const std::string& name) const {
    const YAML::Node c = node_[name];
    if (!c || c.IsNull()) return std::nullopt;
    return Node(c, key_.empty() ? name : key_ + "." + name, source_);
  }
  Node at(std::size_t i) const { return Node(node_[i], key_ + "[" + std::to_string(i) + "]", source_); }

  /// A map whose keys are all among `allowed` (a typo is an error, not a silently ignored key).
  void expectMap(std::initializer_list<const char*> allowed) const {
    if (!node_.IsMap()) fail("expected a mapping of keys");
    for (const auto& kv : node_) {
      const std::string k = kv.first.as<std::string>();
      if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return k == a; })) {
        std::string list;
        for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        Node(kv.first, key_.empty() ? k : key_ + "." + k, source_).fail("unknown key (known here: " + list + ")");
      }
    }
  }
  std::string text() const {
    if (!node_.IsScalar()) fail("expected a single value");
    return node_.Scalar();
  }
  double number() const {
    const std::string t = text();
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(t, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != t.size() || t.empty() || !std::isfinite(v)) fail("'" + t + "' is not a finite number");
    return v;
  }
  int integer() const {
    const double v = number();
    if (v != std::round(v) || std::abs(v) > 1e9) fail("'" + text() + "' is not an integer");
    return static_cast<int>(v);
  }
  /// A mapping's keys, in the file's order.
  std::vector<std::string> keys() const {
    if (!node_.IsMap()) fail("expected a mapping of keys");
    std::vector<std::string> out;
    for (const auto& kv : node_) out.push_back(kv.first.as<std::string>());
    return out;
  }
  std::vector<std::string> texts() const {
    if (!node_.IsSequence()) fail("expected a list");
    std::vector<std::string> out;
    for (std::size_t i = 0; i < node_.size(); ++i) out.push_back(at(i).text());
    return out;
  }

 private:
  YAML::Node node_;
  std::string key_;
  const std::string* source_;
};

std::string textOr(const Node& n, const char* key, const std::string& fallback) {
  const auto c = n.child(key);
  return c ? c->text() : fallback;
}

MountingDescription readMounting(const Node& n) {
  n.expectMap({"x", "y", "z", "roll", "pitch", "yaw"});
  MountingDescription m;
  auto num = [&](const char* k, double& v) {
    if (const auto c = n.child(k)) v = c->number();
  };
  num("x", m.x);
  num("y", m.y);
  num("z", m.z);
  num("roll", m.roll);
  num("pitch", m.pitch);
  num("yaw", m.yaw);
  return m;
}

void readDoppler(const Node& n, RadarPointFields& f) {
  if (n.isScalar() && n.text() == "none") {
    f.doppler = DopplerKind::None;
    return;
  }
  n.expectMap({"radial", "sign", "vx", "vy"});
  const auto radial = n.child("radial");
  const auto vx = n.child("vx"), vy = n.child("vy");
  if (radial && (vx || vy)) n.fail("give either 'radial' or 'vx' and 'vy', not both");
  if (radial) {
    f.doppler = DopplerKind::Radial;
    f.radial = radial->text();
    const std::string sign = textOr(n, "sign", "receding");
    if (sign == "receding")
      f.radial_sign = 1.0;
    else if (sign == "approaching")
      f.radial_sign = -1.0;
    else
      n.child("sign")->fail("'" + sign +
                            "': the sign is 'receding' (positive when the target moves away) or "
                            "'approaching' (positive when it comes closer)");
    return;
  }
  if (!vx || !vy) n.fail("needs 'radial' (one field) or both 'vx' and 'vy' (the velocity in the sensor frame)");
  if (n.child("sign")) n.child("sign")->fail("a sign is for a radial field; vx and vy are in the sensor's axes");
  f.doppler = DopplerKind::Components;
  f.vx = vx->text();
  f.vy = vy->text();
}

/// Two field names or two numbers: [a, b].
std::pair<Node, Node> pairOf(const Node& n) {
  if (!n.isSequence() || n.size() != 2) n.fail("expected a list of two: [along x, along y]");
  return {n.at(0), n.at(1)};
}

void readAccuracy(const Node& n, RadarPointFields& f) {
  if (n.isScalar()) {
    if (n.text() != "model") n.fail("'" + n.text() + "': a single value must be 'model' (the data-sheet model)");
    f.accuracy = AccuracyKind::Model;
    return;
  }
  n.expectMap({"ars408_rms", "rms", "fixed"});
  if (n.size() != 1) n.fail("give one of ars408_rms, rms, fixed");
  if (const auto c = n.child("ars408_rms")) {
    const auto [a, b] = pairOf(*c);
    f.accuracy = AccuracyKind::Ars408Rms;
    f.accuracy_x = a.text();
    f.accuracy_y = b.text();
  } else if (const auto r = n.child("rms")) {
    const auto [a, b] = pairOf(*r);
    f.accuracy = AccuracyKind::RmsFields;
    f.accuracy_x = a.text();
    f.accuracy_y = b.text();
  } else if (const auto x = n.child("fixed")) {
    const auto [a, b] = pairOf(*x);
    f.accuracy = AccuracyKind::Fixed;
    f.sigma_x = a.number();
    f.sigma_y = b.number();
    if (!(f.sigma_x > 0) || !(f.sigma_y > 0)) x->fail("standard deviations must be > 0 (m)");
  }
}

/// `spherical_accuracy: {range: M, azimuth_deg: D, elevation_deg: D}`, each > 0.
void readSphericalAccuracy(const Node& n, RadarPointFields& f) {
  n.expectMap({"range", "azimuth_deg", "elevation_deg"});
  SphericalSigmas s;
  double* value[] = {&s.range, &s.azimuth_deg, &s.elevation_deg};
  const char* key[] = {"range", "azimuth_deg", "elevation_deg"};
  for (int i = 0; i < 3; ++i) {
    const auto c = n.child(key[i]);
    if (!c) n.fail(std::string("missing key '") + key[i] + "' (1 sigma: range m, azimuth_deg and elevation_deg deg)");
    *value[i] = c->number();
    if (!(*value[i] > 0)) c->fail("must be > 0");
  }
  f.spherical = s;
}

/// `time: FIELD` (seconds) or `time: {field: FIELD, unit: s|ms|us|ns}`: each detection's measurement
/// time relative to its message's stamp (the driver's per-point time).
void readTime(const Node& n, RadarPointFields& f) {
  if (!n.isMap()) {
    f.time = n.text();
    return;
  }
  n.expectMap({"field", "unit"});
  const auto field = n.child("field");
  if (!field) n.fail("missing key 'field' (the per-point time's field)");
  f.time = field->text();
  const std::string unit = textOr(n, "unit", "s");
  const std::pair<const char*, double> units[] = {{"s", 1.0}, {"ms", 1e-3}, {"us", 1e-6}, {"ns", 1e-9}};
  const auto it = std::find_if(std::begin(units), std::end(units), [&](const auto& u) { return unit == u.first; });
  if (it == std::end(units)) n.child("unit")->fail("unknown unit '" + unit + "' (s, ms, us, ns)");
  f.time_scale = it->second;
}

/// `keep:` or `keep_doppler:`: field: [the integer values kept, ...].
std::vector<std::pair<std::string, std::vector<int>>> keepLists(const Node& n, const char* key) {
  std::vector<std::pair<std::string, std::vector<int>>> lists;
  const auto k = n.child(key);
  if (!k) return lists;
  if (!k->isMap()) k->fail("expected field: [values kept, ...]");
  for (const std::string& name : k->keys()) {
    // A key without a value (`keep: {state: }`), or one a YAML alias made no scalar, has no child.
    const std::optional<Node> child = k->child(name);
    if (!child) k->fail("'" + name + "': expected a list of the integer values kept");
    const Node& values = *child;
    if (!values.isSequence()) values.fail("expected a list of the integer values kept");
    std::vector<int> v;
    for (std::size_t i = 0; i < values.size(); ++i) v.push_back(values.at(i).integer());
    lists.emplace_back(name, v);
  }
  return lists;
}

RadarPointFields readFields(const Node& n) {
  n.expectMap({"position", "doppler", "rcs", "power", "accuracy", "spherical_accuracy", "time", "max_range", "keep",
               "keep_doppler"});
  RadarPointFields f;
  f.doppler = DopplerKind::None;
  if (const auto p = n.child("position")) {
    const std::vector<std::string> xyz = p->texts();
    if (xyz.size() != 2 && xyz.size() != 3) p->fail("expected [x, y] or [x, y, z] field names");
    f.x = xyz[0];
    f.y = xyz[1];
    f.z = xyz.size() == 3 ? xyz[2] : "";
  }
  const auto doppler = n.child("doppler");
  if (!doppler) n.fail("missing key 'doppler' (radial: FIELD, or vx: FIELD and vy: FIELD, or none)");
  readDoppler(*doppler, f);
  f.rcs = textOr(n, "rcs", "");
  f.power = textOr(n, "power", "");
  if (const auto a = n.child("accuracy")) readAccuracy(*a, f);
  if (const auto a = n.child("spherical_accuracy")) readSphericalAccuracy(*a, f);
  if (const auto t = n.child("time")) readTime(*t, f);
  if (const auto r = n.child("max_range")) {
    f.max_range = r->number();
    if (!(f.max_range > 0)) r->fail("must be > 0 (m)");
  }
  f.keep = keepLists(n, "keep");
  f.keep_doppler = keepLists(n, "keep_doppler");
  return f;
}

PolarImageDescription readPolar(const Node& n) {
  n.expectMap({"rows", "range_resolution", "range_offset_bins", "azimuth_zero", "azimuth_offset", "clockwise", "stamp",
               "sweep_period", "max_range"});
  PolarImageDescription p;
  const std::string rows = textOr(n, "rows", "");
  if (rows == "azimuth")
    p.rows_are_azimuths = true;
  else if (rows == "range")
    p.rows_are_azimuths = false;
  else if (rows.empty())
    n.fail("missing key 'rows': azimuth (a row an azimuth) or range (a column an azimuth)");
  else
    n.child("rows")->fail("'" + rows + "': rows are azimuth (a row an azimuth) or range (a column an azimuth)");
  const auto res = n.child("range_resolution");
  if (!res) n.fail("missing key 'range_resolution' (m per bin: the image does not carry it)");
  p.convention.range_resolution = res->number();
  if (!(p.convention.range_resolution > 0)) res->fail("must be > 0 (m per bin)");
  if (const auto c = n.child("range_offset_bins")) p.convention.range_offset_bins = c->number();
  if (const auto c = n.child("azimuth_zero")) p.convention.azimuth_zero = c->number();
  if (const auto c = n.child("azimuth_offset")) p.azimuth_offset = c->number();
  if (const auto c = n.child("clockwise")) {
    const std::string t = c->text();
    if (t != "true" && t != "false") c->fail("'" + t + "': true (azimuths grow clockwise seen from above) or false");
    p.convention.clockwise = t == "true";
  }
  const std::string stamp = textOr(n, "stamp", "start");
  if (stamp == "start")
    p.stamp_position = 0.0;
  else if (stamp == "middle")
    p.stamp_position = 0.5;
  else if (stamp == "end")
    p.stamp_position = 1.0;
  else
    n.child("stamp")->fail("'" + stamp + "': the header stamp is the sweep's start, middle or end");
  if (const auto c = n.child("sweep_period")) {
    p.sweep_period = c->number();
    if (!(p.sweep_period > 0)) c->fail("must be > 0 (s: one turn of the radar)");
  }
  if (const auto r = n.child("max_range")) {
    p.max_range = r->number();
    if (!(p.max_range > 0)) r->fail("must be > 0 (m)");
  }
  return p;
}

RadarDescription readRadar(const Node& n) {
  n.expectMap({"name", "topic", "kind", "frame", "mounting", "fields", "polar"});
  RadarDescription r;
  const auto topic = n.child("topic");
  if (!topic) n.fail("missing key 'topic' (the ROS topic of its messages)");
  r.topic = topic->text();
  if (r.topic.empty()) topic->fail("empty topic");
  r.name = textOr(n, "name", r.topic);
  if (r.name.empty()) n.child("name")->fail("empty name (a tag without a value is one)");
  const std::string kind = textOr(n, "kind", "point_cloud");
  if (kind == "point_cloud")
    r.kind = RadarKind::PointCloud;
  else if (kind == "scanning")
    r.kind = RadarKind::Scanning;
  else
    n.child("kind")->fail("'" + kind + "': the kind is point_cloud or scanning");
  r.frame = textOr(n, "frame", "");
  if (const auto m = n.child("mounting")) r.mounting = readMounting(*m);
  if (r.kind == RadarKind::Scanning) {
    // The scanning pipeline's poses are the radar's own (as for the dataset folders): a mounting
    // has nothing to act on, and point fields nothing to name.
    if (n.child("mounting"))
      n.child("mounting")
          ->fail(
              "a scanning radar's odometry is the radar's own: give no mounting (its heading is "
              "polar.azimuth_zero)");
    if (n.child("fields")) n.child("fields")->fail("a scanning radar has an image, not point fields: give 'polar'");
    const auto polar = n.child("polar");
    if (!polar) n.fail("missing key 'polar' (how the sweep lies in its sensor_msgs/Image)");
    r.polar = readPolar(*polar);
    return r;
  }
  if (n.child("polar")) n.child("polar")->fail("'polar' is for a scanning radar (kind: scanning)");
  const auto fields = n.child("fields");
  if (!fields) n.fail("missing key 'fields' (the names of its point fields)");
  r.fields = readFields(*fields);
  return r;
}

void readGroundTruth(const Node& n, SensorDescription& d) {
  if (n.isScalar()) {
    d.ground_truth_topic = n.text();
    return;
  }
  n.expectMap({"topic", "parent", "child"});
  const auto topic = n.child("topic");
  if (!topic) n.fail("missing key 'topic'");
  d.ground_truth_topic = topic->text();
  d.ground_truth_parent = textOr(n, "parent", d.ground_truth_parent);
  d.ground_truth_child = textOr(n, "child", d.ground_truth_child);
}

SensorDescription readDescription(const Node& root, const std::string& source) {
  root.expectMap(
      {"name", "radars", "reference", "base_frame", "stamps", "imu", "imu_mounting", "speed", "ground_truth"});
  SensorDescription d;
  d.source = source;
  d.name = textOr(root, "name", "");
  d.base_frame = textOr(root, "base_frame", d.base_frame);
  const std::string stamps = textOr(root, "stamps", "auto");
  if (stamps == "header")
    d.stamps = StampSource::Header;
  else if (stamps == "receive")
    d.stamps = StampSource::Receive;
  else if (stamps == "auto")
    d.stamps = StampSource::Auto;
  else
    root.child("stamps")->fail("'" + stamps + "': stamps are header, receive or auto");
  d.imu_topic = textOr(root, "imu", "");
  if (const auto m = root.child("imu_mounting")) d.imu_mounting = readMounting(*m);
  d.speed_topic = textOr(root, "speed", "");
  if (const auto gt = root.child("ground_truth")) readGroundTruth(*gt, d);
  const auto radars = root.child("radars");
  if (!radars) root.fail("missing key 'radars' (a list: one entry a radar)");
  if (!radars->isSequence() || radars->size() == 0) radars->fail("expected a list of at least one radar");
  std::set<std::string> names, topics;
  for (std::size_t i = 0; i < radars->size(); ++i) {
    RadarDescription r = readRadar(radars->at(i));
    if (!names.insert(r.name).second) radars->at(i).fail("a second radar named '" + r.name + "'");
    if (!topics.insert(r.topic).second) radars->at(i).fail("a second radar on topic '" + r.topic + "'");
    d.radars.push_back(std::move(r));
  }
  const auto scanning = std::count_if(d.radars.begin(), d.radars.end(),
                                      [](const RadarDescription& r) { return r.kind == RadarKind::Scanning; });
  if (scanning > 0 && d.radars.size() > 1)
    radars->fail("a scanning radar is run alone: describe one scanning radar, or point-cloud radars only");
  d.reference = textOr(root, "reference", "");
  if (!d.reference.empty() && !names.count(d.reference))
    root.child("reference")->fail("'" + d.reference + "' is none of the radars' names");
  return d;
}

}  // namespace

SensorDescription parseSensorDescription(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    if (e.mark.line >= 0) throw IoError(source, static_cast<std::size_t>(e.mark.line) + 1, "not valid YAML: " + e.msg);
    throw IoError(source, "not valid YAML: " + e.msg);
  }
  if (!root || root.IsNull()) throw IoError(source, "empty: a sensor description needs at least 'radars'");
  try {
    return readDescription(Node(root, "", &source), source);
  } catch (const YAML::Exception& e) {
    throw IoError(source, std::string("malformed: ") + e.what());
  }
}

std::string sensorPresetDirectory() {
  // RADAR_NDT_SENSOR_PRESETS overrides; installed, the share folder; in a build tree, the source's.
  if (const char* env = std::getenv("RADAR_NDT_SENSOR_PRESETS"); env && *env) return env;
  std::error_code ec;
  if (fs::is_directory(RADAR_NDT_SENSOR_PRESETS_INSTALL, ec)) return RADAR_NDT_SENSOR_PRESETS_INSTALL;
  return RADAR_NDT_SENSOR_PRESETS_BUILD;
}

std::vector<std::string> sensorPresets() {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(sensorPresetDirectory(), ec))
    if (e.path().extension() == ".yaml") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

SensorDescription readSensorDescription(const std::string& path) {
  const std::string prefix = "preset:";
  if (path.compare(0, prefix.size(), prefix) == 0) {
    const std::string name = path.substr(prefix.size());
    const std::vector<std::string> presets = sensorPresets();
    if (std::find(presets.begin(), presets.end(), name) == presets.end()) {
      std::string list;
      for (const auto& p : presets) list += (list.empty() ? "" : ", ") + p;
      throw IoError(path, "no such preset (presets in " + sensorPresetDirectory() + ": " + list + ")");
    }
    SensorDescription d = readSensorDescription(sensorPresetDirectory() + "/" + name + ".yaml");
    return d;
  }
  return parseSensorDescription(detail::readWholeFile(path), path);
}

Eigen::Matrix3d imuRotation(const SensorDescription& d) {
  return d.imu_mounting ? Eigen::Matrix3d(d.imu_mounting->transform().linear()) : Eigen::Matrix3d::Identity();
}

double imuYawRate(const SensorDescription& d, const Eigen::Vector3d& gyro) {
  return d.imu_mounting ? imuRotation(d).row(2).dot(gyro) : gyro.z();
}

}  // namespace radar_ndt

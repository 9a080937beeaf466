#include "radar_ndt/io/nuscenes_can_bus.h"

#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/io_error.h"
#include "read_file.h"

namespace radar_ndt {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// Python's json.dump writes NaN, Infinity and -Infinity bare; JSON has no such words, so they
/// become null (outside strings) before parsing.
std::string nullNonFinite(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  bool in_string = false;
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (in_string) {
      out += c;
      if (c == '\\' && i + 1 < text.size())
        out += text[++i];
      else if (c == '"')
        in_string = false;
      ++i;
      continue;
    }
    std::size_t word = 0;
    for (const char* w : {"-Infinity", "Infinity", "NaN"})
      if (text.compare(i, std::char_traits<char>::length(w), w) == 0) {
        word = std::char_traits<char>::length(w);
        break;
      }
    if (word) {
      out += "null";
      i += word;
      continue;
    }
    in_string = c == '"';
    out += c;
    ++i;
  }
  return out;
}

/// The value of `message`[key] (or its element `index`): NaN for null, IoError for anything else
/// that is not a number.
double valueOf(const json& message, const std::string& key, int index, const std::string& file, std::size_t i) {
  const auto where = [&] { return "message " + std::to_string(i) + ": '" + key + "'"; };
  const auto it = message.find(key);
  if (it == message.end()) throw IoError(file, where() + " is missing");
  const json* v = &*it;
  if (index >= 0) {
    if (!v->is_array() || v->size() <= static_cast<std::size_t>(index))
      throw IoError(file, where() + " is not an array of at least " + std::to_string(index + 1) + " numbers");
    v = &(*v)[static_cast<std::size_t>(index)];
  }
  if (v->is_null()) return std::numeric_limits<double>::quiet_NaN();
  if (!v->is_number()) throw IoError(file, where() + " is not a number");
  return v->get<double>();
}

/// A CAN bus message file as the devkit writes it: a JSON list (NaN and Infinity allowed).
json readMessages(const std::string& file) {
  json messages;
  try {
    messages = json::parse(nullNonFinite(detail::readWholeFile(file)));
  } catch (const json::exception& e) {
    throw IoError(file, std::string("invalid JSON: ") + e.what());
  }
  if (!messages.is_array()) throw IoError(file, "expected a JSON list of messages");
  return messages;
}

}  // namespace

TimeSeries readCanBusSeries(const std::string& file, const std::vector<std::string>& keys, int index,
                            std::size_t* dropped) {
  const json messages = readMessages(file);
  TimeSeries series;
  for (std::size_t i = 0; i < messages.size(); ++i) {
    const json& m = messages[i];
    if (!m.is_object()) throw IoError(file, "message " + std::to_string(i) + " is not a JSON object");
    const auto t = m.find("utime");
    if (t == m.end() || !t->is_number_integer())
      throw IoError(file, "message " + std::to_string(i) + ": 'utime' is missing or not an integer");
    const std::int64_t utime = t->get<std::int64_t>();
    double value = 0;
    for (const std::string& key : keys) value += valueOf(m, key, index, file, i) / static_cast<double>(keys.size());
    if (!series.empty() && utime < series.stamps_us.back())
      throw IoError(file, "message " + std::to_string(i) + ": utime " + std::to_string(utime) +
                              " runs back in time (the one before is " + std::to_string(series.stamps_us.back()) + ")");
    if (!std::isfinite(value)) {
      if (dropped) ++*dropped;
      continue;
    }
    if (!series.empty() && utime == series.stamps_us.back()) continue;
    series.stamps_us.push_back(utime);
    series.values.push_back(value);
  }
  return series;
}

std::optional<std::vector<CanImuMessage>> readNuScenesImuMessages(const std::string& dataroot,
                                                                  const std::string& scene_name) {
  const fs::path dir = fs::path(dataroot) / "can_bus";
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return std::nullopt;
  const std::string file = (dir / (scene_name + "_ms_imu.json")).string();
  const json messages = readMessages(file);
  std::vector<CanImuMessage> out;
  for (std::size_t i = 0; i < messages.size(); ++i) {
    const json& m = messages[i];
    if (!m.is_object() || !m.contains("utime") || !m["utime"].is_number_integer())
      throw IoError(file, "message " + std::to_string(i) + ": 'utime' is missing or not an integer");
    CanImuMessage c;
    c.utime = m["utime"].get<std::int64_t>();
    for (int k = 0; k < 3; ++k) {
      c.rotation_rate[k] = valueOf(m, "rotation_rate", k, file, i);
      c.linear_accel[k] = valueOf(m, "linear_accel", k, file, i);
    }
    for (int k = 0; k < 4; ++k) c.q[static_cast<std::size_t>(k)] = valueOf(m, "q", k, file, i);
    out.push_back(c);
  }
  return out;
}

std::optional<VehicleSignals> readNuScenesCanBus(const std::string& dataroot, const std::string& scene_name) {
  const fs::path dir = fs::path(dataroot) / "can_bus";
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return std::nullopt;
  const auto file = [&](const char* message) {
    const std::string path = (dir / (scene_name + "_" + message + ".json")).string();
    if (!fs::exists(path, ec))
      throw IoError(path, std::string("missing: the CAN bus folder has no ") + message + " message for " + scene_name);
    return path;
  };
  VehicleSignals s;
  s.source = dir.string();
  s.yaw_rate = readCanBusSeries(file("ms_imu"), {"rotation_rate"}, 2, &s.dropped);
  const std::string wheels = file("zoe_veh_info");
  s.rear_wheel_rpm = readCanBusSeries(wheels, {"RL_wheel_speed", "RR_wheel_speed"}, -1, &s.dropped);
  if (s.yaw_rate.empty()) throw IoError(file("ms_imu"), "no message with a yaw rate");
  if (s.rear_wheel_rpm.empty()) throw IoError(wheels, "no message with both rear wheels' speeds");
  return s;
}

void writeNuScenesCanBus(const std::string& dataroot, const std::string& scene_name,
                         const std::vector<CanImuMessage>& imu, const std::vector<CanWheelMessage>& wheels) {
  const fs::path dir = fs::path(dataroot) / "can_bus";
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError(dir.string(), "cannot create: " + ec.message());
  const auto vec = [](std::ostringstream& s, const char* key, const double* v, int n) {
    s << ", \"" << key << "\": [";
    for (int i = 0; i < n; ++i) s << (i ? ", " : "") << v[i];
    s << ']';
  };
  std::ostringstream a;
  a.precision(17);
  a << '[';
  for (std::size_t i = 0; i < imu.size(); ++i) {
    const CanImuMessage& m = imu[i];
    a << (i ? ",\n " : "") << "{\"utime\": " << m.utime;
    vec(a, "rotation_rate", m.rotation_rate.data(), 3);
    vec(a, "linear_accel", m.linear_accel.data(), 3);
    vec(a, "q", m.q.data(), 4);
    a << '}';
  }
  a << "]\n";
  writeFileAtomically((dir / (scene_name + "_ms_imu.json")).string(), a.str());
  std::ostringstream w;
  w.precision(17);
  w << '[';
  for (std::size_t i = 0; i < wheels.size(); ++i) {
    const CanWheelMessage& m = wheels[i];
    w << (i ? ",\n " : "") << "{\"utime\": " << m.utime << ", \"FL_wheel_speed\": " << m.fl
      << ", \"FR_wheel_speed\": " << m.fr << ", \"RL_wheel_speed\": " << m.rl << ", \"RR_wheel_speed\": " << m.rr
      << '}';
  }
  w << "]\n";
  writeFileAtomically((dir / (scene_name + "_zoe_veh_info.json")).string(), w.str());
}

}  // namespace radar_ndt

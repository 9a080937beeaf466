#include "batch_plan.h"
#include "radar_ndt/io/dataset_format.h"

#include <fnmatch.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/io/sensor_description.h"

namespace radar_ndt {
namespace batch {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::vector<std::string> splitList(const std::string& text, char sep) {
  std::vector<std::string> out;
  std::stringstream s(text);
  for (std::string item; std::getline(s, item, sep);) out.push_back(item);
  if (!text.empty() && text.back() == sep) out.push_back("");
  return out;
}

/// Whether `dir` is laid out as `format`'s reader wants a sequence.
bool isSequence(const std::string& format, const fs::path& dir) {
  std::error_code ec;
  const DatasetFormat f = parseEnum<DatasetFormat>(format);
  if (f == DatasetFormat::Oxford) return fs::is_regular_file(dir / "radar.timestamps", ec);
  if (f == DatasetFormat::Radiate) return fs::is_regular_file(dir / "Navtech_Polar.txt", ec);
  if (f == DatasetFormat::Boreas) {
    if (!fs::is_directory(dir / "radar", ec)) return false;
    for (const auto& e : fs::directory_iterator(dir / "radar", ec))
      if (e.path().extension() == ".png") return true;
  }
  return false;
}

bool hasGroundTruth(const PlanRequest& request, const std::string& path) {
  const std::string& format = request.format;
  std::error_code ec;
  if (format == "nuscenes") return true;  // the ego poses
  // A bag's ground truth is what its description names; a bag without that topic fails its task
  // with the reader's message, as a run by hand would.
  if (format == "rosbag") return !readSensorDescription(request.sensors).ground_truth_topic.empty();
  if (format == "oxford") return fs::is_regular_file(fs::path(path) / "gt" / "radar_odometry.csv", ec);
  if (format == "boreas") return fs::is_regular_file(fs::path(path) / "applanix" / "radar_poses.csv", ec);
  return false;
}

std::string readText(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw IoError(path, "cannot be opened");
  std::string text;
  char buf[65536];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) text.append(buf, n);
  std::fclose(f);
  return text;
}

}  // namespace

SettingAxis parseSettingAxis(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw std::invalid_argument("--set " + text + ": expected NAME=V1[,V2...], e.g. grid=3,3.75");
  SettingAxis axis{text.substr(0, eq), splitList(text.substr(eq + 1), ',')};
  if (axis.name.rfind("--", 0) == 0) axis.name = axis.name.substr(2);
  for (const auto& v : axis.values)
    if (v.empty() || v.find_first_of(" \t\n") != std::string::npos)
      throw std::invalid_argument("--set " + text + ": a value is empty or holds white space");
  if (axis.name.find_first_of(" \t\n=") != std::string::npos)
    throw std::invalid_argument("--set " + text + ": the name holds white space");
  return axis;
}

std::vector<Sequence> findSequences(const std::string& format, const std::string& root,
                                    const std::vector<std::string>& names, const std::string& glob) {
  std::vector<Sequence> found;
  const DatasetFormat f = parseEnum<DatasetFormat>(format);
  if (f == DatasetFormat::NuScenes) {
    const NuScenesDataset dataset(root);
    for (const auto& s : dataset.scenes()) found.push_back({s.name, fs::absolute(root).lexically_normal().string()});
  } else if (f == DatasetFormat::Rosbag) {
    // A bag, or every *.bag of a folder (not its subfolders): a sequence each, named by its stem.
    std::error_code ec;
    const fs::path r = fs::absolute(root).lexically_normal();
    if (fs::is_regular_file(r, ec)) {
      found.push_back({r.stem().string(), r.string()});
    } else {
      if (!fs::is_directory(r, ec)) throw IoError(root, "is neither a bag nor a folder");
      for (const auto& e : fs::directory_iterator(r, ec))
        if (e.is_regular_file() && e.path().extension() == ".bag")
          found.push_back({e.path().stem().string(), e.path().string()});
    }
  } else {  // a scanning radar's sequence folders
    std::error_code ec;
    if (!fs::is_directory(root, ec)) throw IoError(root, "is not a folder");
    const fs::path r = fs::absolute(root).lexically_normal();
    if (isSequence(format, r))
      found.push_back({r.filename().empty() ? r.parent_path().filename().string() : r.filename().string(), r.string()});
    for (const auto& e : fs::directory_iterator(r, ec))
      if (e.is_directory() && isSequence(format, e.path()))
        found.push_back({e.path().filename().string(), e.path().string()});
  }
  std::sort(found.begin(), found.end(), [](const Sequence& a, const Sequence& b) { return a.name < b.name; });
  if (!names.empty()) {
    std::vector<Sequence> chosen;
    for (const auto& n : names) {
      const auto it = std::find_if(found.begin(), found.end(), [&](const Sequence& s) { return s.name == n; });
      if (it == found.end()) throw std::invalid_argument("sequence " + n + " is not in " + root);
      chosen.push_back(*it);
    }
    found = chosen;
  }
  if (!glob.empty())
    found.erase(std::remove_if(found.begin(), found.end(),
                               [&](const Sequence& s) { return fnmatch(glob.c_str(), s.name.c_str(), 0) != 0; }),
                found.end());
  if (found.empty()) throw std::invalid_argument("no " + format + " sequence found in " + root);
  return found;
}

std::string Task::settingsText() const {
  if (settings.empty()) return "default";
  std::string s;
  for (const auto& [name, value] : settings) s += (s.empty() ? "" : " ") + name + "=" + value;
  return s;
}

std::string taskId(const std::string& sequence, const std::string& method,
                   const std::vector<std::pair<std::string, std::string>>& settings) {
  std::uint64_t h = 1469598103934665603ull;
  auto add = [&](const std::string& s) {
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
    h = (h ^ 0x1f) * 1099511628211ull;  // a separator no name contains
  };
  add(sequence);
  add(method);
  for (const auto& [name, value] : settings) {
    add(name);
    add(value);
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

std::string taskDir(const std::string& run_dir, const std::string& id) {
  return (fs::path(run_dir) / "tasks" / id).string();
}

std::vector<Task> expandPlan(const PlanRequest& request, const std::vector<Sequence>& sequences) {
  if (request.format == "rosbag" && request.sensors.empty())
    throw std::invalid_argument("--format rosbag needs --sensors FILE.yaml (or preset:NAME)");
  for (const auto& axis : request.settings)
    for (const auto& v : axis.values)
      if (axis.is_switch && v != "on" && v != "off")
        throw std::invalid_argument("--set " + axis.name + "=" + v + ": a switch's values are on and off");
  // Every combination of the axes' values, the last axis fastest.
  std::vector<std::vector<std::pair<std::string, std::string>>> grid{{}};
  for (const auto& axis : request.settings) {
    std::vector<std::vector<std::pair<std::string, std::string>>> next;
    for (const auto& partial : grid)
      for (const auto& v : axis.values) {
        next.push_back(partial);
        next.back().emplace_back(axis.name, v);
      }
    grid = next;
  }
  std::vector<Task> tasks;
  std::set<std::string> ids;
  for (const auto& seq : sequences)
    for (const auto& method : request.methods)
      for (const auto& settings : grid) {
        Task t{taskId(seq.name, method, settings), seq.name, method, settings, {}};
        if (!ids.insert(t.id).second)
          throw std::invalid_argument("two tasks with the same sequence, method and settings: " + seq.name + " " +
                                      method + " " + t.settingsText());
        auto& c = t.command;
        c = {request.odometry_app, "--format", request.format};
        if (request.format == "nuscenes")
          c.insert(c.end(), {"--dataroot", seq.path, "--scene", seq.name});
        else if (request.format == "rosbag")
          c.insert(c.end(), {"--bag", seq.path, "--sensors", request.sensors});
        else
          c.insert(c.end(), {"--sequence", seq.path});
        c.insert(c.end(), {"--method", method});
        for (std::size_t i = 0; i < settings.size(); ++i) {
          const auto& [name, value] = settings[i];
          if (!request.settings[i].is_switch)
            c.insert(c.end(), {"--" + name, value});
          else if (value == "on")
            c.push_back("--" + name);
        }
        if (hasGroundTruth(request, seq.path)) c.insert(c.end(), {"--eval", "--metric", "all"});
        c.insert(c.end(),
                 {"--json", "-q", "--out", (fs::path(taskDir(request.run_dir, t.id)) / "trajectory.txt").string()});
        tasks.push_back(std::move(t));
      }
  return tasks;
}

std::string shellQuote(const std::string& arg) {
  const bool safe = !arg.empty() && std::all_of(arg.begin(), arg.end(), [](char ch) {
    return std::isalnum(static_cast<unsigned char>(ch)) || std::string("@%+=:,./_-").find(ch) != std::string::npos;
  });
  if (safe) return arg;
  std::string q = "'";
  for (char ch : arg) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return q + "'";
}

std::string joinShellWords(const std::vector<std::string>& words) {
  std::string line;
  for (const auto& w : words) line += (line.empty() ? "" : " ") + shellQuote(w);
  return line;
}

std::vector<std::string> splitShellWords(const std::string& line) {
  std::vector<std::string> words;
  std::string word;
  bool in_word = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (ch == ' ') {
      if (in_word) words.push_back(word);
      word.clear();
      in_word = false;
    } else if (ch == '\'') {
      const auto end = line.find('\'', i + 1);
      if (end == std::string::npos) throw std::invalid_argument("unterminated quote in: " + line);
      word += line.substr(i + 1, end - i - 1);
      in_word = true;
      i = end;
    } else if (ch == '\\' && i + 1 < line.size()) {
      word += line[++i];
      in_word = true;
    } else {
      word += ch;
      in_word = true;
    }
  }
  if (in_word) words.push_back(word);
  return words;
}

void writePlan(const Plan& plan) {
  const auto& r = plan.request;
  json sets = json::array();
  for (const auto& a : r.settings) {
    sets.push_back({{"name", a.name}, {"values", a.values}});
    if (a.is_switch) sets.back()["switch"] = true;  // only then: plans without switches read as before
  }
  json seqs = json::array();
  for (const auto& s : plan.sequences) seqs.push_back({{"name", s.name}, {"path", s.path}});
  const json j = {{"version", plan.version},
                  {"git_revision", plan.git_revision},
                  {"format", r.format},
                  {"root", r.root},
                  {"glob", r.glob},
                  {"sensors", r.sensors},
                  {"methods", r.methods},
                  {"settings", sets},
                  {"sequences", seqs},
                  {"odometry_app", r.odometry_app},
                  {"tasks", plan.tasks.size()}};
  fs::create_directories(fs::path(r.run_dir) / "tasks");
  writeFileAtomically((fs::path(r.run_dir) / "plan.json").string(), j.dump(2) + "\n");
  std::string tsv = "# id\tsequence\tmethod\tsettings\tcommand\n";
  for (const auto& t : plan.tasks)
    tsv +=
        t.id + "\t" + t.sequence + "\t" + t.method + "\t" + t.settingsText() + "\t" + joinShellWords(t.command) + "\n";
  writeFileAtomically((fs::path(r.run_dir) / "tasks.tsv").string(), tsv);
}

Plan readPlan(const std::string& run_dir) {
  const std::string plan_path = (fs::path(run_dir) / "plan.json").string();
  const std::string tasks_path = (fs::path(run_dir) / "tasks.tsv").string();
  Plan plan;
  try {
    const json j = json::parse(readText(plan_path));
    auto& r = plan.request;
    plan.version = j.at("version");
    plan.git_revision = j.at("git_revision");
    r.format = j.at("format");
    r.root = j.at("root");
    r.glob = j.at("glob");
    r.sensors = j.value("sensors", "");  // absent in plans written before bags were read
    r.methods = j.at("methods").get<std::vector<std::string>>();
    for (const auto& a : j.at("settings"))
      r.settings.push_back({a.at("name"), a.at("values"), a.value("switch", false)});
    for (const auto& s : j.at("sequences")) plan.sequences.push_back({s.at("name"), s.at("path")});
    r.odometry_app = j.at("odometry_app");
    r.run_dir = fs::absolute(run_dir).lexically_normal().string();
  } catch (const json::exception& e) {
    throw IoError(plan_path, std::string("not a radar_batch plan: ") + e.what());
  }
  std::stringstream lines(readText(tasks_path));
  std::size_t n = 0;
  for (std::string line; std::getline(lines, line);) {
    ++n;
    if (line.empty() || line[0] == '#') continue;
    const auto cols = splitList(line, '\t');
    if (cols.size() != 5) throw IoError(tasks_path, n, "expected 5 tab-separated columns");
    Task t{cols[0], cols[1], cols[2], {}, splitShellWords(cols[4])};
    if (cols[3] != "default")
      for (const auto& kv : splitList(cols[3], ' ')) {
        const auto eq = kv.find('=');
        if (eq == std::string::npos) throw IoError(tasks_path, n, "settings must be NAME=VALUE words");
        t.settings.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
      }
    plan.tasks.push_back(std::move(t));
  }
  return plan;
}

}  // namespace batch
}  // namespace radar_ndt

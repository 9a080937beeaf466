#include "sim_settings.h"

#include <cstdio>
#include <set>
#include <stdexcept>

#include "field_options.h"

namespace radar_ndt {
namespace apps {

namespace {

/// The numeric fields of one table, as settings of SimConfig.
template <typename T>
std::vector<FieldOption<SimConfig>> numericFields(T SimConfig::*part) {
  std::vector<FieldOption<SimConfig>> out;
  for (auto& f : fieldOptions(T{}, true)) {
    if (!f.numeric) continue;
    FieldOption<SimConfig> g;
    g.option = f.option;
    g.field = f.field;
    g.numeric = true;
    g.set = [part, set = f.set](SimConfig& c, const std::string& v) { set(c.*part, v); };
    g.get = [part, get = f.get](const SimConfig& c) { return get(c.*part); };
    out.push_back(std::move(g));
  }
  return out;
}

struct Group {
  const char* name;
  std::vector<FieldOption<SimConfig>> settings;
};

const std::vector<Group>& groups() {
  static const std::vector<Group> all = [] {
    std::vector<Group> g{{"world", numericFields(&SimConfig::world)},
                         {"scanning", numericFields(&SimConfig::scanning)},
                         {"automotive", numericFields(&SimConfig::automotive)},
                         {"imu", numericFields(&SimConfig::imu)},
                         {"wheels", numericFields(&SimConfig::wheels)}};
    std::set<std::string> names;
    for (const auto& group : g)
      for (const auto& s : group.settings)
        if (!names.insert(s.option).second)
          throw std::logic_error("radar_sim: two settings named " + s.option + " (give one a name in its table)");
    return g;
  }();
  return all;
}

}  // namespace

void applySetting(const std::string& assignment, SimConfig& config) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos) throw std::invalid_argument("--set '" + assignment + "': expected name=value");
  const std::string name = assignment.substr(0, eq);
  for (const auto& group : groups())
    for (const auto& s : group.settings)
      if (s.option == name) {
        s.set(config, assignment.substr(eq + 1));
        return;
      }
  throw std::invalid_argument("--set: unknown setting '" + name + "' (see --list-settings)");
}

std::string listSettings(const SimConfig& config) {
  std::string out;
  char line[512];
  for (const auto& group : groups()) {
    out += std::string(group.name) + ":\n";
    for (const auto& s : group.settings) {
      std::snprintf(line, sizeof line, "  %-30s %-10s %s\n", s.option.c_str(), s.get(config).c_str(), s.field.help);
      out += line;
    }
  }
  return out;
}

std::string settingsMarkdown(const std::vector<std::pair<std::string, SimConfig>>& columns) {
  std::string out = "| setting |", rule = "|---|";
  for (const auto& c : columns) out += " " + c.first + " |", rule += "---|";
  out += " meaning |\n" + rule + "---|\n";
  for (const auto& group : groups())
    for (const auto& s : group.settings) {
      out += "| " + std::string(group.name) + ": `" + s.option + "` |";
      for (const auto& c : columns) out += " " + s.get(c.second) + " |";
      out += " " + std::string(s.field.help) + " |\n";
    }
  return out;
}

}  // namespace apps
}  // namespace radar_ndt

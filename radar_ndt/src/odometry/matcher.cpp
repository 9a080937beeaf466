#include "radar_ndt/odometry/matcher.h"

#include <memory>
#include <mutex>
#include <stdexcept>

#include "matchers/builtin_matchers.h"
#include "radar_ndt/odometry/matcher_registry.h"

namespace radar_ndt {

namespace {

/// The registry: the built-in matchers first, then the users' in the order they were added.
struct Registry {
  std::mutex mutex;
  std::vector<std::unique_ptr<MatcherEntry>> entries;  // stable addresses: findMatcher hands out references

  Registry() {
    for (auto& e : matchers::builtins()) entries.push_back(std::make_unique<MatcherEntry>(std::move(e)));
  }
  const MatcherEntry* find(const std::string& name) {
    for (const auto& e : entries)
      if (e->name == name) return e.get();
    return nullptr;
  }
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

void registerMatcher(MatcherEntry entry) {
  if (entry.name.empty()) throw std::invalid_argument("registerMatcher: the matcher has no name");
  if (!entry.make) throw std::invalid_argument("registerMatcher: matcher '" + entry.name + "' has no factory");
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  if (r.find(entry.name)) throw std::invalid_argument("registerMatcher: a matcher '" + entry.name + "' is registered");
  r.entries.push_back(std::make_unique<MatcherEntry>(std::move(entry)));
}

const MatcherEntry& findMatcher(const std::string& name) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  if (const MatcherEntry* e = r.find(name)) return *e;
  std::string names;
  for (const auto& e : r.entries) names += (names.empty() ? "" : ", ") + e->name;
  throw std::invalid_argument("unknown method '" + name + "' (" + names + ")");
}

std::vector<std::string> matcherNames() {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& e : r.entries) names.push_back(e->name);
  return names;
}

std::string matcherChoices() {
  std::string out;
  for (const std::string& name : matcherNames())
    out += (out.empty() ? "" : " | ") + name + " (" + findMatcher(name).help + ")";
  return out;
}

MatcherOptions MatcherOptions::forScanning() {
  MatcherOptions m;
  m.grid = 3.75;
  m.power_shift = 0.333f;
  m.weighted_ndt.cell_lookup = CellLookup::OverlappingGrids;
  return m;
}

MatcherOptions MatcherOptions::forAutomotive() {
  return MatcherOptions();
}

void MatcherOptions::validate() const {
  findMatcher(method);
  checkFields(*this, "MatcherOptions");
  // The grid, power shift and source shift are set above, once for every matcher (makeMatcher
  // hands them to WeightedNDT2D); set in weighted_ndt as well they would have two owners.
  const WeightedNDT2DSettings defaults;
  if (weighted_ndt.resolutions != defaults.resolutions || weighted_ndt.power_shift != defaults.power_shift ||
      weighted_ndt.shift_source_weights != defaults.shift_source_weights)
    throw std::invalid_argument(
        "MatcherOptions: weighted_ndt.resolutions, power_shift and shift_source_weights are MatcherOptions' grid, "
        "power_shift and shift_source_weights: set those");
}

MatcherAdapter makeMatcher(const MatcherOptions& options) {
  options.validate();
  return findMatcher(options.method).make(options);
}

}  // namespace radar_ndt

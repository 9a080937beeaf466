#include "radar_ndt/odometry/matcher_registry_3d.h"

#include <memory>
#include <mutex>
#include <stdexcept>

#include "matchers/builtin_matchers_3d.h"

namespace radar_ndt {

namespace {

/// The registry: the built-in matchers first, then the users' in the order they were added.
struct Registry3D {
  std::mutex mutex;
  std::vector<std::unique_ptr<Matcher3DEntry>> entries;  // stable addresses: findMatcher3D hands out references

  Registry3D() {
    for (auto& e : matchers::builtins3D()) entries.push_back(std::make_unique<Matcher3DEntry>(std::move(e)));
  }
  const Matcher3DEntry* find(const std::string& name) {
    for (const auto& e : entries)
      if (e->name == name) return e.get();
    return nullptr;
  }
};

Registry3D& registry3D() {
  static Registry3D r;
  return r;
}

}  // namespace

void Matcher3DOptions::validate() const {
  ndt.validate();
  checkFields(*this, "Matcher3DOptions");
}

void registerMatcher3D(Matcher3DEntry entry) {
  if (entry.name.empty()) throw std::invalid_argument("registerMatcher3D: the matcher has no name");
  if (!entry.make || !entry.iterations)
    throw std::invalid_argument("registerMatcher3D: matcher '" + entry.name +
                                "' needs a factory and an iteration count");
  Registry3D& r = registry3D();
  std::lock_guard<std::mutex> lock(r.mutex);
  if (r.find(entry.name))
    throw std::invalid_argument("registerMatcher3D: a matcher '" + entry.name + "' is registered");
  r.entries.push_back(std::make_unique<Matcher3DEntry>(std::move(entry)));
}

const Matcher3DEntry& findMatcher3D(const std::string& name) {
  Registry3D& r = registry3D();
  std::lock_guard<std::mutex> lock(r.mutex);
  if (const Matcher3DEntry* e = r.find(name)) return *e;
  std::string names;
  for (const auto& e : r.entries) names += (names.empty() ? "" : ", ") + e->name;
  throw std::invalid_argument("unknown 3D method '" + name + "' (" + names + ")");
}

std::vector<std::string> matcher3DNames() {
  Registry3D& r = registry3D();
  std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& e : r.entries) names.push_back(e->name);
  return names;
}

}  // namespace radar_ndt

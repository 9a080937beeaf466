#include "radar_ndt/io/recording.h"

#include <map>
#include <mutex>
#include <stdexcept>

namespace radar_ndt {

namespace {
std::mutex& registryMutex() {
  static std::mutex m;
  return m;
}
std::map<std::string, RecordingReader>& registry() {
  static std::map<std::string, RecordingReader> readers;
  return readers;
}
}  // namespace

void registerRecordingReader(const std::string& format, RecordingReader reader) {
  const std::lock_guard<std::mutex> lock(registryMutex());
  registry()[format] = std::move(reader);
}

bool hasRecordingReader(const std::string& format) {
  const std::lock_guard<std::mutex> lock(registryMutex());
  return registry().count(format) > 0;
}

Recording readRecording(const std::string& format, const std::string& path, const SensorDescription& sensors) {
  RecordingReader reader;
  {
    const std::lock_guard<std::mutex> lock(registryMutex());
    const auto it = registry().find(format);
    if (it == registry().end())
      throw std::invalid_argument("--format " + format + ": this build reads no " + format +
                                  " recordings (Debian's ROS 1 was not found when it was built: bash .ci/deps)");
    reader = it->second;
  }
  return reader(path, sensors);
}

}  // namespace radar_ndt

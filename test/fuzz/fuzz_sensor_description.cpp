// libFuzzer target: sensor descriptions (parseSensorDescription: YAML). Every input either gives a
// description whose radars have a topic, a name and positive ranges, or an IoError.
#include <cmath>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/sensor_description.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using radar_ndt::fuzz::finding;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const radar_ndt::SensorDescription d = radar_ndt::parseSensorDescription(text, "fuzz.yaml");
    if (d.radars.empty()) finding("a description without radars was returned");
    for (const auto& r : d.radars) {
      if (r.topic.empty() || r.name.empty()) finding("a radar without topic or name");
      if (!(r.fields.max_range > 0)) finding("a non-positive range");
      if (r.fields.accuracy == radar_ndt::AccuracyKind::Fixed && !(r.fields.sigma_x > 0 && r.fields.sigma_y > 0))
        finding("a fixed accuracy that is not positive");
      if (r.mounting && !r.mounting->transform().matrix().allFinite()) finding("a non-finite mounting");
    }
  } catch (const radar_ndt::IoError& e) {
    if (std::string(e.what()).find("fuzz.yaml") == std::string::npos) finding("an error that does not name the file");
  }
  return 0;
}

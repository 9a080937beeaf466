#pragma once
// The settings a run is given, whoever gives them: the command line (its text parsed by each
// field's type), Python's keywords and the ROS node's parameters (their own types handed over), all
// as field paths with typed values (radar_ndt/field_values.h), applied here in one way over the
// defaults for the radar a run reads.

#include <string>
#include <vector>

#include "radar_ndt/field_values.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/inertial_run.h"
#include "radar_ndt/pipeline/scanning_run.h"

namespace radar_ndt {

/// A setting as a caller gives it: a field's path ("odometry.gyro.bias_walk"), its value, and how
/// the caller names it in messages ("--gyro-bias-walk", "~odometry/gyro/bias_walk"; empty: the path).
struct Setting {
  std::string path;
  FieldValue value;
  std::string name;
  const std::string& spelled() const { return name.empty() ? path : name; }
};
using Settings = std::vector<Setting>;

/// The last setting of `path` in `given`; null when none.
const Setting* findSetting(const Settings& given, const std::string& path);

/// Why a setting was refused: what the Python bindings turn into TypeError (a name or a type) or
/// ValueError (a value).
class SettingError : public std::invalid_argument {
 public:
  enum class Why { NoSuchSetting, OtherPipeline, NotThisLayout, Type, Value };
  SettingError(Why why, const std::string& what) : std::invalid_argument(what), why_(why) {}
  Why why() const { return why_; }

 private:
  Why why_;
};

/// The automotive run options `given` asks for, over `defaults`: the method given (else the
/// defaults') set with what it needs (withMethod); the paper's mode, when given, without the
/// Doppler fusion as the paper has it (unless odometry.fuse_doppler is given too); then every setting
/// in order; validated. A setting that contradicts its method is refused by validate(), naming it.
/// SettingError for a path that is no field of these options (naming the scanning pipeline when it
/// is one of its), a value of the wrong type or out of range; std::invalid_argument from validate().
AutomotiveRunOptions automotiveRunOptions(const Settings& given, const AutomotiveRunOptions& defaults = {});

/// The scanning run options `given` asks for, over `defaults` (the defaults for the sequence's
/// radar: defaultScanningOptions), validated. `layout` (oxford, radiate, boreas, rosbag) is what
/// the run reads: a setting of another layout's reader (sequence.boreas.*) is refused, as one of the
/// automotive pipeline is.
ScanningRunOptions scanningRunOptions(const Settings& given, const std::string& layout,
                                      const ScanningRunOptions& defaults = {});

/// The 6-DoF run options `given` asks for, over `defaults`, validated: a recording of a 4D radar
/// run with a 6-DoF method (isInertialMethod). SettingError as above, naming the automotive
/// pipeline for its settings.
InertialRunOptions inertialRunOptions(const Settings& given, const InertialRunOptions& defaults = {});

/// The settings as one line, "path = value, ..." (the node prints what it was given).
std::string settingsText(const Settings& given);

}  // namespace radar_ndt

#pragma once
// The node's private parameters as the run's settings (docs/ros.md): a parameter named after a
// field's path ('/' for '.') sets that field to the parameter's own value, typed as XmlRpc holds it
// (a double stays a double, a boolean sets a switch's field to that boolean), through the library's
// one way of applying settings (radar_ndt/pipeline/run_settings.h). The node's own parameters are
// not settings; any other private parameter is refused by the pipeline that runs, naming it.

#include <map>
#include <string>

#include <xmlrpcpp/XmlRpcValue.h>

#include "radar_ndt/pipeline/run_settings.h"

namespace radar_ndt {
namespace node {

/// The node's own parameters, beside the run's settings.
constexpr const char* kNodeParameters[] = {"sensors", "cycle_period", "flush_after", "odom_frame"};

/// `v` as a setting's value: a boolean, an integer, a double, text, or a list of these;
/// std::invalid_argument naming `name` for a struct or a date.
FieldValue fieldValueOf(XmlRpc::XmlRpcValue& v, const std::string& name);

/// The settings among the private parameters `params` (by name under the node's namespace:
/// "odometry/fuse_doppler"), in name order; the node's own are left out.
Settings settingsFromParameters(std::map<std::string, XmlRpc::XmlRpcValue> params);

}  // namespace node
}  // namespace radar_ndt

#include "node/node_parameters.h"

#include <algorithm>
#include <stdexcept>

namespace radar_ndt {
namespace node {

FieldValue fieldValueOf(XmlRpc::XmlRpcValue& v, const std::string& name) {
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean: return FieldValue(static_cast<bool>(v));
    case XmlRpc::XmlRpcValue::TypeInt: return FieldValue(static_cast<int>(v));
    case XmlRpc::XmlRpcValue::TypeDouble: return FieldValue(static_cast<double>(v));
    case XmlRpc::XmlRpcValue::TypeString: return FieldValue(static_cast<std::string>(v));
    case XmlRpc::XmlRpcValue::TypeArray: {
      FieldValue::List items;
      for (int i = 0; i < v.size(); ++i) items.push_back(fieldValueOf(v[i], name));
      return FieldValue(std::move(items));
    }
    default: throw std::invalid_argument("~" + name + ": expected a boolean, a number, text or a list of these");
  }
}

Settings settingsFromParameters(std::map<std::string, XmlRpc::XmlRpcValue> params) {
  Settings given;
  for (auto& [name, value] : params) {
    if (std::find(std::begin(kNodeParameters), std::end(kNodeParameters), name) != std::end(kNodeParameters)) continue;
    std::string path = name;
    std::replace(path.begin(), path.end(), '/', '.');
    given.push_back({path, fieldValueOf(value, name), "~" + name});
  }
  return given;
}

}  // namespace node
}  // namespace radar_ndt

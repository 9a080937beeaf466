// Keyword arguments onto the options structs (keywords.h).

#include "keywords.h"

#include <vector>

namespace radar_ndt {
namespace python {

namespace {

/// The public attributes of a bound options struct: its fields.
std::string fieldList(const py::handle& target) {
  std::string out;
  for (const py::handle name : py::module_::import("builtins").attr("dir")(target)) {
    const std::string n = py::str(name);
    if (n.empty() || n[0] == '_' || n == "validate" || n == "paper") continue;
    out += (out.empty() ? "" : ", ") + n;
  }
  return out;
}

}  // namespace

void applyKeywords(const py::handle& target, const py::dict& kw, const std::string& where, const char* extra) {
  for (auto item : kw) {
    const std::string key = py::str(item.first);
    if (key.empty() || key[0] == '_' || !py::hasattr(target, key.c_str()) || key == "validate" || key == "paper") {
      std::string known = fieldList(target);
      if (extra && *extra) known = std::string(extra) + ", " + known;
      throw py::type_error("unknown option '" + key + "' of " + where + "; options: " + known);
    }
    const std::string path = where + "." + key;
    if (py::isinstance<py::dict>(item.second)) {
      const py::object nested = target.attr(key.c_str());
      if (py::hasattr(nested, "__copy__") && py::hasattr(nested, "__deepcopy__")) {  // an options struct
        applyKeywords(nested, item.second.cast<py::dict>(), path);
        continue;
      }
    }
    try {
      target.attr(key.c_str()) = item.second;
    } catch (py::error_already_set& e) {
      if (!e.matches(PyExc_TypeError)) throw;
      throw py::type_error(path + ": cannot take " + std::string(py::str(py::repr(item.second))) + " (" +
                           std::string(py::str(item.second.get_type().attr("__name__"))) + ")");
    }
  }
}

py::dict without(const py::dict& kw, std::initializer_list<const char*> names) {
  py::dict out;
  for (auto item : kw) {
    const std::string k = py::str(item.first);
    bool skip = false;
    for (const char* n : names) skip = skip || k == n;
    if (!skip) out[item.first] = item.second;
  }
  return out;
}

}  // namespace python
}  // namespace radar_ndt

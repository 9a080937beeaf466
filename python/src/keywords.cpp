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

namespace {

FieldValue valueOf(const py::handle& v, const std::string& path) {
  if (py::isinstance<py::bool_>(v)) return FieldValue(v.cast<bool>());
  if (py::isinstance<py::int_>(v) ||
      (py::hasattr(v, "__index__") && !py::isinstance<py::float_>(v) && !py::isinstance<py::str>(v)))
    return FieldValue(v.cast<long long>());
  if (py::isinstance<py::float_>(v)) return FieldValue(v.cast<double>());
  if (py::isinstance<py::str>(v)) return FieldValue(v.cast<std::string>());
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    FieldValue::List items;
    for (const py::handle item : v) items.push_back(valueOf(item, path));
    return FieldValue(std::move(items));
  }
  if (py::hasattr(v, "__float__")) return FieldValue(v.cast<double>());  // numpy's floats
  throw py::type_error(path + ": cannot take " + std::string(py::str(py::repr(v))) + " (" +
                       std::string(py::str(v.get_type().attr("__name__"))) +
                       "): give a bool, a number, text, a list, or a dict of a struct's fields");
}

void flatten(const py::dict& kw, const std::string& prefix, Settings& out) {
  for (auto item : kw) {
    const std::string key = py::str(item.first);
    const std::string path = prefix.empty() && key == "method" ? "matcher.method" : prefix + key;
    if (py::isinstance<py::dict>(item.second))
      flatten(item.second.cast<py::dict>(), path + ".", out);
    else
      out.push_back({path, valueOf(item.second, path), path});
  }
}

}  // namespace

Settings settingsFromKeywords(const py::dict& kw) {
  Settings out;
  flatten(kw, "", out);
  return out;
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

#pragma once
// Keyword arguments onto the options structs (bind_options.cpp): `grid=4.0` sets a field,
// `odometry={"keyframes": {"distance": 0}}` sets nested ones. An unknown name or a value of the
// wrong type raises TypeError naming the field; ranges are checked by the struct's validate()
// (ValueError naming the setting).

#include <string>

#include <pybind11/pybind11.h>

#include "radar_ndt/pipeline/run_settings.h"

namespace radar_ndt {
namespace python {

namespace py = pybind11;

/// Sets `kw` onto the bound object `target` (nested dicts onto its nested structs). `where` names
/// the struct in errors; `extra` lists keywords the caller takes itself (for the error message).
void applyKeywords(const py::handle& target, const py::dict& kw, const std::string& where, const char* extra = "");

/// A copy of `base` with `kw` applied.
template <typename T>
T withKeywords(T base, const py::dict& kw, const std::string& where, const char* extra = "") {
  applyKeywords(py::cast(&base, py::return_value_policy::reference), kw, where, extra);
  return base;
}

/// `value` as a T, or TypeError naming the keyword `key`.
template <typename T>
T keywordAs(const py::handle& value, const std::string& key) {
  try {
    return value.cast<T>();
  } catch (const py::cast_error&) {
    throw py::type_error(key + ": cannot take " + std::string(py::str(py::repr(value))));
  }
}

/// Keyword arguments as a run's settings (radar_ndt/pipeline/run_settings.h): nested dicts give
/// the paths (odometry={"gyro": {"bias_walk": 1e-7}} is odometry.gyro.bias_walk), each value handed
/// over as its own type (bool, int, float, str, a list of these); `method` is matcher.method.
/// TypeError for a value of another type (an options object: give its fields as a dict).
Settings settingsFromKeywords(const py::dict& kw);

/// `kw` without the keys in `names` (the ones a function takes itself).
py::dict without(const py::dict& kw, std::initializer_list<const char*> names);

}  // namespace python
}  // namespace radar_ndt

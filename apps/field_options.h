#pragma once
// The command line from the field tables (radar_ndt/fields.h): every field of an options struct
// (nested tables entered) that names a command-line option becomes one, with its help, unit,
// choices and default from the table and the default options. The text is parsed as the field's
// type and set through the field's typed setter (radar_ndt/field_values.h, what Python and the ROS
// node set fields through too), which checks its bounds; the struct's validate() checks the rest.
// Used by radar_odometry, radar_paper_tables and radar_batch (the pipelines' run options) and by
// radar_sim (the simulator's settings). No field is listed here by hand.

#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "radar_ndt/field_values.h"

namespace radar_ndt {
namespace apps {

/// One command-line option made from a field of R's table.
template <typename R>
struct FieldOption {
  std::string option;        ///< "keyframe-distance"
  std::string path;          ///< where the field lives: "odometry.keyframes.distance"
  std::string scope;         ///< "" or the layout it applies to alone ("oxford")
  Field field;               ///< the table's description
  bool off_switch = false;   ///< a switch: turns the flag off (--no-gate) or on (--imu)
  bool numeric = false;      ///< a number (radar_sim's settings are these)
  std::string choices;       ///< "polar | rms", the matcher registry's list, ...
  std::string default_text;  ///< the value in the defaults it was made from
  /// The value the option gives its field: the text parsed as the field's type (a switch: the
  /// value its table says, the text ignored).
  std::function<FieldValue(const std::string&)> value;
  std::function<void(R&, const std::string&)> set;  ///< sets the field to value(text), checked
  std::function<std::string(const R&)> get;         ///< the value as text
};

namespace detail {

inline std::string numberText(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

/// A value as the command line and the docs spell it: a number with 6 digits, a spelled flag by its
/// names, a list joined by commas.
inline std::string optionText(const FieldValue& v, const Field& f) {
  switch (v.kind()) {
    case FieldValue::Kind::Bool:
      if (f.true_name) return v.boolean() ? f.true_name : f.false_name;
      return v.boolean() ? "true" : "false";
    case FieldValue::Kind::Integer: return numberText(static_cast<double>(v.integer()));
    case FieldValue::Kind::Real: return numberText(v.real());
    case FieldValue::Kind::Text: return v.text();
    default: {
      std::string out;
      for (const FieldValue& item : v.list()) out += (out.empty() ? "" : ",") + optionText(item, f);
      return out;
    }
  }
}

template <typename M>
std::string choicesOf(const Field& f) {
  if (f.choices_text) return f.choices_text();
  if constexpr (std::is_enum_v<M>) {
    std::string out;
    for (const auto& n : EnumNames<M>::names)
      if (*n.help) out += (out.empty() ? "" : " | ") + std::string(n.name) + " (" + n.help + ")";
    return out;
  }
  if (f.true_name) return std::string(f.true_name) + " | " + f.false_name;
  return "";
}

/// The choices of each field of R's tables, in the order of fieldEntries<R>() (an enumeration's
/// name table is reached through its type).
template <typename T>
void collectChoices(std::vector<std::string>& out) {
  T::fields([&](auto member, const Field& f) {
    using M = std::remove_reference_t<decltype(std::declval<T&>().*member)>;
    if constexpr (HasFields<M>::value)
      collectChoices<M>(out);
    else
      out.push_back(choicesOf<M>(f));
  });
}

}  // namespace detail

/// The options R's field tables name (nested tables entered), in table order, with `defaults`'
/// values as their defaults. `all`: every field that is not itself a struct, under its own name
/// where it names no option (radar_sim's settings). Each sets its field through the field's typed
/// setter (radar_ndt/field_values.h): the text parsed as the field's type, a switch setting the
/// value its table says.
template <typename R>
std::vector<FieldOption<R>> fieldOptions(const R& defaults, bool all = false) {
  std::vector<std::string> choices;
  detail::collectChoices<R>(choices);
  std::vector<FieldOption<R>> out;
  std::size_t k = 0;
  for (const FieldEntry<R>& e : fieldEntries<R>()) {
    const std::string& choice = choices[k++];
    const Field& f = e.field;
    if (!f.cli_name && !all) continue;
    FieldOption<R> o;
    o.option = f.cli_name ? f.cli_name : f.name;
    o.path = e.path;
    o.scope = e.scope;
    o.field = f;
    o.off_switch = f.off_switch_help != nullptr;
    o.numeric = e.is_number;
    o.choices = choice;
    o.default_text = detail::optionText(e.get(defaults), f);
    const std::string name = "--" + o.option;
    if (o.off_switch)
      o.value = [f](const std::string&) { return FieldValue(f.switch_sets); };
    else
      o.value = [&e, name](const std::string& text) { return e.parse(text, name); };
    o.set = [&e, name, value = o.value](R& r, const std::string& text) { e.set(r, value(text), name); };
    o.get = [&e, f](const R& r) { return detail::optionText(e.get(r), f); };
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace apps
}  // namespace radar_ndt

#pragma once
// The command line from the field tables (radar_ndt/fields.h): every field of an options struct
// (nested tables entered) that names a command-line option becomes one, with its help, unit,
// choices and default from the table and the default options. A value is parsed as the field's
// type and checked against its bounds here; the struct's validate() checks the rest. Used by
// radar_odometry, radar_paper_tables and radar_batch (the pipelines' run options) and by radar_sim
// (the simulator's settings). No field is listed here by hand.

#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "radar_ndt/fields.h"

namespace radar_ndt {
namespace apps {

/// One command-line option made from a field of R's table.
template <typename R>
struct FieldOption {
  std::string option;                               ///< "keyframe-distance"
  std::string path;                                 ///< where the field lives: "odometry.keyframes.distance"
  std::string scope;                                ///< "" or the layout it applies to alone ("oxford")
  Field field;                                      ///< the table's description
  bool off_switch = false;                          ///< a switch: turns the flag off (--no-gate) or on (--imu)
  bool numeric = false;                             ///< a number (radar_sim's settings are these)
  std::string choices;                              ///< "polar | rms", the matcher registry's list, ...
  std::string default_text;                         ///< the value in the defaults it was made from
  std::function<void(R&, const std::string&)> set;  ///< parses and sets (a switch: the text is ignored)
  std::function<std::string(const R&)> get;         ///< the value as text
};

namespace detail {

[[noreturn]] inline void badValue(const std::string& option, const std::string& text, const std::string& why) {
  throw std::invalid_argument("--" + option + " '" + text + "': " + why);
}

inline double parseNumber(const std::string& option, const std::string& text) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size()) badValue(option, text, "not a number");
  return v;
}

inline std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream list(text);  // "A,B" or "A, B"
  for (std::string item; std::getline(list, item, ',');) {
    const std::size_t b = item.find_first_not_of(' ');
    if (b != std::string::npos) out.push_back(item.substr(b, item.find_last_not_of(' ') - b + 1));
  }
  return out;
}

inline std::string numberText(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

/// A number for a field of type M: within the field's bounds and, for an integer, whole and
/// within the type.
template <typename M>
M toNumber(const std::string& option, const std::string& text, const Field& f) {
  const double v = parseNumber(option, text);
  if (!f.bounds.contains(v)) badValue(option, text, "must be " + f.bounds.text());
  if constexpr (std::is_integral_v<M>) {
    if (v != static_cast<double>(static_cast<long long>(v))) badValue(option, text, "not a whole number");
    if (v < static_cast<double>(std::numeric_limits<M>::lowest()) ||
        v > static_cast<double>(std::numeric_limits<M>::max()))
      badValue(option, text, "out of range");
  }
  return static_cast<M>(v);
}

template <typename M>
void assign(M& value, const std::string& option, const std::string& text, const Field& f) {
  if constexpr (std::is_same_v<M, bool>) {
    if (f.true_name && text == f.true_name)
      value = true;
    else if (f.false_name && text == f.false_name)
      value = false;
    else if (f.true_name)
      badValue(option, text, std::string("must be ") + f.true_name + " or " + f.false_name);
    else if (text == "1" || text == "true")
      value = true;
    else if (text == "0" || text == "false")
      value = false;
    else
      badValue(option, text, "must be true or false (1 or 0)");
  } else if constexpr (std::is_enum_v<M>) {
    try {
      value = parseEnum<M>(text);
    } catch (const std::invalid_argument& e) {
      badValue(option, text, e.what());
    }
  } else if constexpr (std::is_arithmetic_v<M>) {
    value = toNumber<M>(option, text, f);
  } else if constexpr (std::is_same_v<M, std::string>) {
    value = text;
  } else if constexpr (IsVector<M>::value) {
    M out;
    for (const std::string& item : splitList(text)) {
      typename M::value_type v{};
      assign(v, option, item, f);
      out.push_back(v);
    }
    value = out;
  } else {
    static_assert(sizeof(M) == 0, "a field type the command line cannot set");
  }
}

template <typename M>
std::string text(const M& value, const Field& f) {
  if constexpr (std::is_same_v<M, bool>) {
    if (f.true_name) return value ? f.true_name : f.false_name;
    return value ? "true" : "false";
  } else if constexpr (std::is_enum_v<M>) {
    return toString(value);
  } else if constexpr (std::is_arithmetic_v<M>) {
    return numberText(static_cast<double>(value));
  } else if constexpr (std::is_same_v<M, std::string>) {
    return value;
  } else {
    std::string out;
    for (const auto& v : value) out += (out.empty() ? "" : ",") + text(v, f);
    return out;
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

template <typename R, typename T, typename Get>
void collect(const Get& get, const std::string& path, const char* scope, const R& defaults,
             std::vector<FieldOption<R>>& out, bool all) {
  T::fields([&](auto member, const Field& f) {
    using M = std::remove_reference_t<decltype(std::declval<T&>().*member)>;
    auto sub = [get, member](R& r) -> M& { return get(r).*member; };
    const std::string here = path.empty() ? f.name : path + "." + f.name;
    if constexpr (HasFields<M>::value) {
      collect<R, M>(sub, here, f.scope_name ? f.scope_name : scope, defaults, out, all);
    } else {
      if (!f.cli_name && !all) return;
      FieldOption<R> o;
      o.option = f.cli_name ? f.cli_name : f.name;
      o.path = here;
      o.scope = scope ? scope : "";
      o.field = f;
      o.off_switch = f.off_switch_help != nullptr;
      o.numeric = std::is_arithmetic_v<M> && !std::is_same_v<M, bool>;
      o.choices = choicesOf<M>(f);
      R copy = defaults;
      o.default_text = text(sub(copy), f);
      const std::string option = o.option;
      if (o.off_switch)
        o.set = [sub, f](R& r, const std::string&) {
          if constexpr (std::is_same_v<M, bool>) sub(r) = f.switch_sets;
        };
      else
        o.set = [sub, option, f](R& r, const std::string& value) { assign(sub(r), option, value, f); };
      o.get = [sub, f](const R& r) {
        R copy_of = r;
        return text(sub(copy_of), f);
      };
      out.push_back(std::move(o));
    }
  });
}

}  // namespace detail

/// The options R's field tables name (nested tables entered), in table order, with `defaults`'
/// values as their defaults. `all`: every field that is not itself a struct, under its own name
/// where it names no option (radar_sim's settings).
template <typename R>
std::vector<FieldOption<R>> fieldOptions(const R& defaults, bool all = false) {
  std::vector<FieldOption<R>> out;
  detail::collect<R, R>([](R& r) -> R& { return r; }, "", nullptr, defaults, out, all);
  return out;
}

}  // namespace apps
}  // namespace radar_ndt

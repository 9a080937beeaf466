#pragma once
// Field tables: one description of each options struct's fields, beside the struct, from which
// everything that lists a field is produced: validate()'s range checks and messages, the
// command-line options of the apps, the Python attributes and keywords, radar_sim's settings,
// radar_batch's --set check and the docs' option tables. A struct takes part by a static member
// template that hands each field to a visitor:
//
//   struct KeyframeOptions {
//     double distance = 10.0;
//     template <typename Visit> static void fields(Visit&& visit) {
//       visit(&KeyframeOptions::distance, Field("distance", "replace the keyframe after this distance")
//                                             .unit("m").atLeast(0).cli("keyframe-distance"));
//     }
//   };
//
// A field is a number (bounded by its Field), a flag, a string, a list of numbers or strings, an
// enumeration with a name table (EnumNames, below), or another options struct with a table of its
// own (entered by those who walk the tree, validated by its own validate()). Enumerations get one
// name table each: their parse, print, help and Python spellings all come from it.

#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace radar_ndt {

// ---- enumerations ---------------------------------------------------------------------------

template <typename E>
struct EnumName {
  E value;
  const char* name;  ///< as the command line, Python and the JSON outputs spell it
  const char* help;  ///< one phrase; empty for an alias (a second name of a value listed before)
};

/// Specialised beside each enumeration:
///   template <> struct EnumNames<CompensationMode> {
///     static constexpr const char* what = "compensation mode";
///     static constexpr EnumName<CompensationMode> names[] = {{CompensationMode::Rounds, "rounds", "..."}, ...};
///   };
/// The first name of a value is how it prints; later ones are aliases the parser also takes.
template <typename E>
struct EnumNames;

template <typename E, typename = void>
struct HasEnumNames : std::false_type {};
template <typename E>
struct HasEnumNames<E, std::void_t<decltype(EnumNames<E>::names)>> : std::true_type {};

/// The value's name ("?" for a value the table lacks).
template <typename E, std::enable_if_t<HasEnumNames<E>::value, int> = 0>
const char* toString(E value) {
  for (const auto& n : EnumNames<E>::names)
    if (n.value == value) return n.name;
  return "?";
}

/// The names a value prints as, joined by `separator` (aliases left out).
template <typename E>
std::string enumChoices(const char* separator = ", ") {
  std::string out;
  for (const auto& n : EnumNames<E>::names)
    if (*n.help) out += (out.empty() ? "" : separator) + std::string(n.name);
  return out;
}

/// The value named `text`; std::invalid_argument naming the enumeration and its names otherwise.
template <typename E>
E parseEnum(const std::string& text) {
  for (const auto& n : EnumNames<E>::names)
    if (text == n.name) return n.value;
  std::string all;
  for (const auto& n : EnumNames<E>::names) all += (all.empty() ? "" : ", ") + std::string(n.name);
  throw std::invalid_argument("unknown " + std::string(EnumNames<E>::what) + " '" + text + "' (" + all + ")");
}

// ---- fields ---------------------------------------------------------------------------------

/// The values a number may take: [lo, hi] with either end open; finite, unless `infinite` (where
/// infinity means "no bound").
struct Bounds {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  bool infinite = false;

  bool contains(double v) const {
    if (std::isnan(v)) return false;
    if (std::isinf(v)) return infinite && (v > 0 ? !std::isfinite(hi) : !std::isfinite(lo));
    return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  /// "> 0", ">= 1", "in [0, 1)", "finite".
  std::string text() const {
    const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
    auto num = [](double v) {
      std::ostringstream s;
      s << v;
      return s.str();
    };
    const std::string or_infinite = infinite ? " (infinity: no bound)" : "";
    if (has_lo && has_hi)
      return "in " + std::string(lo_open ? "(" : "[") + num(lo) + ", " + num(hi) + (hi_open ? ")" : "]");
    if (has_lo) return (lo_open ? "> " : ">= ") + num(lo) + or_infinite;
    if (has_hi) return (hi_open ? "< " : "<= ") + num(hi) + or_infinite;
    return infinite ? "a number" : "finite";
  }
};

/// One field's description: its name (the C++ member's, Python's attribute and keyword), help,
/// unit and bounds, and, when the apps take it, its command-line name.
struct Field {
  const char* name = "";
  const char* help = "";
  const char* unit_text = "";
  Bounds bounds;
  /// The command-line option (radar_odometry --keyframe-distance; radar_sim --set NAME); null:
  /// not on the command line.
  const char* cli_name = nullptr;
  /// A flag the command line sets with a switch (cli_name, e.g. "no-gate"): what that does.
  const char* off_switch_help = nullptr;
  /// What that switch sets the flag to: false (offSwitch, "--no-gate") or true (onSwitch, "--imu").
  bool switch_sets = false;
  /// A flag the command line spells as one of two names (--points polar|cartesian).
  const char* false_name = nullptr;
  const char* true_name = nullptr;
  /// A nested struct that is one of several alternatives (the dataset layouts of a sequence): its
  /// command-line options apply only when the apps read that layout.
  const char* scope_name = nullptr;
  /// A string naming one of a list kept elsewhere (the registry of matchers): that list, for help.
  std::string (*choices_text)() = nullptr;

  Field() = default;
  Field(const char* n, const char* h) : name(n), help(h) {}
  Field unit(const char* u) const {
    return with([&](Field& f) { f.unit_text = u; });
  }
  /// >= v
  Field atLeast(double v) const {
    return with([&](Field& f) { f.bounds.lo = v, f.bounds.lo_open = false; });
  }
  /// > v
  Field above(double v) const {
    return with([&](Field& f) { f.bounds.lo = v, f.bounds.lo_open = true; });
  }
  /// <= v
  Field atMost(double v) const {
    return with([&](Field& f) { f.bounds.hi = v, f.bounds.hi_open = false; });
  }
  /// < v
  Field below(double v) const {
    return with([&](Field& f) { f.bounds.hi = v, f.bounds.hi_open = true; });
  }
  Field positive() const { return above(0); }
  /// Infinity is allowed too: no bound.
  Field orInfinite() const {
    return with([&](Field& f) { f.bounds.infinite = true; });
  }
  Field cli(const char* option) const {
    return with([&](Field& f) { f.cli_name = option; });
  }
  /// On the command line as a switch that turns the flag off, doing what `help_text` says.
  Field offSwitch(const char* option, const char* help_text) const {
    return with([&](Field& f) { f.cli_name = option, f.off_switch_help = help_text, f.switch_sets = false; });
  }
  /// On the command line as a switch that turns the flag on, doing what `help_text` says.
  Field onSwitch(const char* option, const char* help_text) const {
    return with([&](Field& f) { f.cli_name = option, f.off_switch_help = help_text, f.switch_sets = true; });
  }
  /// On the command line as `option` taking `if_false` or `if_true`.
  Field spelled(const char* option, const char* if_false, const char* if_true) const {
    return with([&](Field& f) { f.cli_name = option, f.false_name = if_false, f.true_name = if_true; });
  }
  Field scope(const char* layout) const {
    return with([&](Field& f) { f.scope_name = layout; });
  }
  Field choices(std::string (*list)()) const {
    return with([&](Field& f) { f.choices_text = list; });
  }

 private:
  template <typename F>
  Field with(F&& change) const {
    Field f = *this;
    change(f);
    return f;
  }
};

namespace detail {
struct AnyVisitor {
  template <typename Member>
  void operator()(Member, const Field&) const {}
};
}  // namespace detail

/// Whether T is an options struct with a field table.
template <typename T, typename = void>
struct HasFields : std::false_type {};
template <typename T>
struct HasFields<T, std::void_t<decltype(T::fields(std::declval<detail::AnyVisitor>()))>> : std::true_type {};

template <typename T>
struct IsVector : std::false_type {};
template <typename T, typename A>
struct IsVector<std::vector<T, A>> : std::true_type {};

namespace detail {
template <typename T, typename = void>
struct HasValidate : std::false_type {};
template <typename T>
struct HasValidate<T, std::void_t<decltype(std::declval<const T&>().validate())>> : std::true_type {};

inline std::string numberText(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
}  // namespace detail

/// Checks every field of `options` against its table: numbers (and each number of a list) within
/// their bounds, nested structs by their own validate() or, without one, by their table. Throws
/// std::invalid_argument "<what>: <field> must be <bounds> (got <value>)".
template <typename T>
void checkFields(const T& options, const char* what) {
  T::fields([&](auto member, const Field& f) {
    using M = std::remove_cv_t<std::remove_reference_t<decltype(options.*member)>>;
    auto check = [&](double v) {
      if (!f.bounds.contains(v))
        throw std::invalid_argument(std::string(what) + ": " + f.name + " must be " + f.bounds.text() + " (got " +
                                    detail::numberText(v) + ")");
    };
    if constexpr (std::is_arithmetic_v<M> && !std::is_same_v<M, bool>) {
      check(static_cast<double>(options.*member));
    } else if constexpr (IsVector<M>::value) {
      if constexpr (std::is_arithmetic_v<typename M::value_type>)
        for (const auto v : options.*member) check(static_cast<double>(v));
    } else if constexpr (detail::HasValidate<M>::value) {
      (options.*member).validate();
    } else if constexpr (HasFields<M>::value) {
      checkFields(options.*member, (std::string(what) + "." + f.name).c_str());
    }
  });
}

/// Calls `f(field, value)` for every field of `options`, `value` a reference to the member (const
/// when `options` is); nested structs are handed over as they are, not entered.
template <typename T, typename F>
void forEachField(T& options, F&& f) {
  using Plain = std::remove_const_t<T>;
  Plain::fields([&](auto member, const Field& field) { f(field, options.*member); });
}

}  // namespace radar_ndt

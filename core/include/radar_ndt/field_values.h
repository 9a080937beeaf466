#pragma once
// Setting an options struct's fields by path with typed values: what the command line, Python and
// the ROS node all set options through. A field's description (radar_ndt/fields.h) says what it
// is; how a caller spells it is the caller's: the command line parses its text into a FieldValue by
// the field's type (parseFieldText), Python and ROS hand their own types over as they are (a double
// stays a double, a parameter named after a switch's field sets that field's value, true or false).
//
//   AutomotiveRunOptions o;
//   setField(o, "odometry.gyro.bias_walk", FieldValue(1e-7), "~odometry/gyro/bias_walk");
//   for (const auto& f : fieldEntries<AutomotiveRunOptions>()) ...   // every field, by path

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "radar_ndt/fields.h"

namespace radar_ndt {

/// A value as a caller holds it: a boolean, an integer, a real number, text, or a list of these.
class FieldValue {
 public:
  enum class Kind { Bool, Integer, Real, Text, List };
  using List = std::vector<FieldValue>;

  FieldValue(bool v) : kind_(Kind::Bool), b_(v) {}                                        // NOLINT: implicit by design
  FieldValue(int v) : kind_(Kind::Integer), i_(v) {}                                      // NOLINT
  FieldValue(long v) : kind_(Kind::Integer), i_(v) {}                                     // NOLINT
  FieldValue(long long v) : kind_(Kind::Integer), i_(v) {}                                // NOLINT
  FieldValue(double v) : kind_(Kind::Real), d_(v) {}                                      // NOLINT
  FieldValue(std::string v) : kind_(Kind::Text), s_(std::move(v)) {}                      // NOLINT
  FieldValue(const char* v) : kind_(Kind::Text), s_(v) {}                                 // NOLINT
  FieldValue(List v) : kind_(Kind::List), list_(std::make_shared<List>(std::move(v))) {}  // NOLINT

  Kind kind() const { return kind_; }
  bool boolean() const { return b_; }
  long long integer() const { return i_; }
  double real() const { return d_; }
  const std::string& text() const { return s_; }
  const List& list() const { return *list_; }

  bool operator==(const FieldValue& o) const {
    if (kind_ != o.kind_) return false;
    switch (kind_) {
      case Kind::Bool: return b_ == o.b_;
      case Kind::Integer: return i_ == o.i_;
      case Kind::Real: return d_ == o.d_ || (d_ != d_ && o.d_ != o.d_);
      case Kind::Text: return s_ == o.s_;
      default: return *list_ == *o.list_;
    }
  }
  bool operator!=(const FieldValue& o) const { return !(*this == o); }

  /// As messages and --show-options print it: true, 12, 1e-07 (every digit a double needs), "text",
  /// [a, b].
  std::string str() const {
    std::ostringstream out;
    switch (kind_) {
      case Kind::Bool: out << (b_ ? "true" : "false"); break;
      case Kind::Integer: out << i_; break;
      case Kind::Real: out.precision(17), out << d_; break;
      case Kind::Text: out << '"' << s_ << '"'; break;
      default:
        out << '[';
        for (std::size_t k = 0; k < list_->size(); ++k) out << (k ? ", " : "") << (*list_)[k].str();
        out << ']';
    }
    return out.str();
  }
  /// "a boolean", "an integer", ...: what a message says the caller gave.
  const char* kindName() const {
    switch (kind_) {
      case Kind::Bool: return "a boolean";
      case Kind::Integer: return "an integer";
      case Kind::Real: return "a real number";
      case Kind::Text: return "text";
      default: return "a list";
    }
  }

 private:
  Kind kind_;
  bool b_ = false;
  long long i_ = 0;
  double d_ = 0;
  std::string s_;
  std::shared_ptr<List> list_;
};

/// A value refused by a field: of another type (wrong_type) or outside the field's values.
class FieldValueError : public std::invalid_argument {
 public:
  FieldValueError(const std::string& what, bool wrong_type) : std::invalid_argument(what), wrong_type_(wrong_type) {}
  bool wrongType() const { return wrong_type_; }

 private:
  bool wrong_type_;
};

namespace detail {

[[noreturn]] inline void refuseValue(const std::string& name, const FieldValue& v, const std::string& why,
                                     bool wrong_type = false) {
  throw FieldValueError(name + " " + v.str() + ": " + why, wrong_type);
}

/// What a field of type M takes, for messages.
template <typename M>
std::string expectedOf(const Field& f) {
  if constexpr (std::is_same_v<M, bool>) {
    if (f.true_name) return std::string("true or false, or ") + f.true_name + " or " + f.false_name;
    return "true or false";
  } else if constexpr (std::is_enum_v<M>) {
    return "one of " + enumChoices<M>();
  } else if constexpr (std::is_integral_v<M>) {
    return "a whole number";
  } else if constexpr (std::is_arithmetic_v<M>) {
    return "a number";
  } else if constexpr (std::is_same_v<M, std::string>) {
    return "text";
  } else {
    return "a list of " + expectedOf<typename M::value_type>(f);
  }
}

template <typename M>
void assignValue(M& out, const FieldValue& v, const Field& f, const std::string& name) {
  auto wrong = [&] { refuseValue(name, v, "expects " + expectedOf<M>(f) + ", not " + v.kindName(), true); };
  if constexpr (std::is_same_v<M, bool>) {
    if (v.kind() == FieldValue::Kind::Bool)
      out = v.boolean();
    else if (v.kind() == FieldValue::Kind::Text && f.true_name && v.text() == f.true_name)
      out = true;
    else if (v.kind() == FieldValue::Kind::Text && f.false_name && v.text() == f.false_name)
      out = false;
    else
      wrong();
  } else if constexpr (std::is_enum_v<M>) {
    if (v.kind() != FieldValue::Kind::Text) wrong();
    try {
      out = parseEnum<M>(v.text());
    } catch (const std::invalid_argument& e) {
      refuseValue(name, v, e.what());
    }
  } else if constexpr (std::is_arithmetic_v<M>) {
    double x = 0;
    if (v.kind() == FieldValue::Kind::Integer)
      x = static_cast<double>(v.integer());
    else if (v.kind() == FieldValue::Kind::Real)
      x = v.real();
    else
      wrong();
    if (!f.bounds.contains(x)) refuseValue(name, v, "must be " + f.bounds.text());
    if constexpr (std::is_integral_v<M>) {
      if (v.kind() == FieldValue::Kind::Real && x != static_cast<double>(static_cast<long long>(x)))
        refuseValue(name, v, "not a whole number");
      if (x < static_cast<double>(std::numeric_limits<M>::lowest()) ||
          x > static_cast<double>(std::numeric_limits<M>::max()))
        refuseValue(name, v, "out of range");
      out = v.kind() == FieldValue::Kind::Integer ? static_cast<M>(v.integer()) : static_cast<M>(x);
    } else {
      out = static_cast<M>(x);
    }
  } else if constexpr (std::is_same_v<M, std::string>) {
    if (v.kind() != FieldValue::Kind::Text) wrong();
    out = v.text();
  } else if constexpr (IsVector<M>::value) {
    if (v.kind() != FieldValue::Kind::List) wrong();
    M items;
    for (const FieldValue& item : v.list()) {
      typename M::value_type x{};
      assignValue(x, item, f, name);
      items.push_back(x);
    }
    out = std::move(items);
  } else {
    static_assert(sizeof(M) == 0, "a field type that cannot be set");
  }
}

template <typename M>
FieldValue valueOf(const M& v) {
  if constexpr (std::is_same_v<M, bool>) {
    return FieldValue(v);
  } else if constexpr (std::is_enum_v<M>) {
    return FieldValue(std::string(toString(v)));
  } else if constexpr (std::is_integral_v<M>) {
    return FieldValue(static_cast<long long>(v));
  } else if constexpr (std::is_arithmetic_v<M>) {
    return FieldValue(static_cast<double>(v));
  } else if constexpr (std::is_same_v<M, std::string>) {
    return FieldValue(v);
  } else {
    FieldValue::List items;
    for (const auto& x : v) items.push_back(valueOf(x));
    return FieldValue(std::move(items));
  }
}

/// `text` as a value for a field of type M: "true"/"1" and "false"/"0" for a flag (a flag spelled
/// by two names of its own takes those alone), a number for a number (whole: an integer), a
/// comma-separated list for a list.
template <typename M>
FieldValue textValue(const std::string& text, const Field& f, const std::string& name) {
  if constexpr (std::is_same_v<M, bool>) {
    if (f.true_name) return FieldValue(text);
    if (text == "true" || text == "1") return FieldValue(true);
    if (text == "false" || text == "0") return FieldValue(false);
    return FieldValue(text);
  } else if constexpr (std::is_arithmetic_v<M> && !std::is_enum_v<M>) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != text.size()) throw std::invalid_argument(name + " '" + text + "': not a number");
    if (std::is_integral_v<M> && text.find_first_of(".eE") == std::string::npos &&
        v == static_cast<double>(static_cast<long long>(v)))
      return FieldValue(static_cast<long long>(v));
    return FieldValue(v);
  } else if constexpr (IsVector<M>::value) {
    FieldValue::List items;
    std::stringstream list(text);  // "A,B" or "A, B"
    for (std::string item; std::getline(list, item, ',');) {
      const std::size_t b = item.find_first_not_of(' ');
      if (b != std::string::npos)
        items.push_back(textValue<typename M::value_type>(item.substr(b, item.find_last_not_of(' ') - b + 1), f, name));
    }
    return FieldValue(std::move(items));
  } else {
    return FieldValue(text);
  }
}

}  // namespace detail

/// One field of R's tables (nested tables entered), reached by its path.
template <typename R>
struct FieldEntry {
  std::string path;   ///< "odometry.gyro.bias_walk"
  std::string scope;  ///< "" or the dataset layout it applies to alone (Field::scope)
  Field field;
  bool is_flag = false, is_number = false;
  /// The kind of value the field holds; for a list, also its items'.
  FieldValue::Kind kind = FieldValue::Kind::Bool, item_kind = FieldValue::Kind::Bool;
  /// An enumeration's names (each value's first), in its table's order; empty for other types.
  std::vector<std::string> names;
  /// Sets the field of `r` to `value`; std::invalid_argument naming `name` (the caller's spelling:
  /// "--gyro-bias-walk", "~odometry/gyro/bias_walk") for a value of another type or out of bounds.
  std::function<void(R&, const FieldValue&, const std::string& name)> set;
  std::function<FieldValue(const R&)> get;
  /// The command line's text as a value of this field's type (std::invalid_argument for a
  /// number that is not one).
  std::function<FieldValue(const std::string& text, const std::string& name)> parse;
};

namespace detail {

template <typename M>
constexpr FieldValue::Kind kindOf() {
  if constexpr (std::is_same_v<M, bool>)
    return FieldValue::Kind::Bool;
  else if constexpr (std::is_enum_v<M> || std::is_same_v<M, std::string>)
    return FieldValue::Kind::Text;
  else if constexpr (std::is_integral_v<M>)
    return FieldValue::Kind::Integer;
  else if constexpr (std::is_arithmetic_v<M>)
    return FieldValue::Kind::Real;
  else
    return FieldValue::Kind::List;
}

template <typename R, typename T, typename Get>
void collectEntries(const Get& get, const std::string& path, const char* scope, std::vector<FieldEntry<R>>& out) {
  T::fields([&](auto member, const Field& f) {
    using M = std::remove_reference_t<decltype(std::declval<T&>().*member)>;
    auto sub = [get, member](R& r) -> M& { return get(r).*member; };
    const std::string here = path.empty() ? f.name : path + "." + f.name;
    if constexpr (HasFields<M>::value) {
      collectEntries<R, M>(sub, here, f.scope_name ? f.scope_name : scope, out);
    } else {
      FieldEntry<R> e;
      e.path = here;
      e.scope = scope ? scope : "";
      e.field = f;
      e.is_flag = std::is_same_v<M, bool>;
      e.is_number = std::is_arithmetic_v<M> && !std::is_same_v<M, bool> && !std::is_enum_v<M>;
      e.kind = kindOf<M>();
      if constexpr (IsVector<M>::value) e.item_kind = kindOf<typename M::value_type>();
      if constexpr (std::is_enum_v<M>)
        for (const auto& n : EnumNames<M>::names)
          if (*n.help) e.names.push_back(n.name);
      e.set = [sub, f](R& r, const FieldValue& v, const std::string& name) {
        M value = sub(r);
        assignValue(value, v, f, name);
        sub(r) = value;
      };
      e.get = [sub](const R& r) { return valueOf(sub(const_cast<R&>(r))); };
      e.parse = [f](const std::string& text, const std::string& name) { return textValue<M>(text, f, name); };
      out.push_back(std::move(e));
    }
  });
}

}  // namespace detail

/// Every field of R's tables that is not itself a struct, in table order.
template <typename R>
const std::vector<FieldEntry<R>>& fieldEntries() {
  static const std::vector<FieldEntry<R>> entries = [] {
    std::vector<FieldEntry<R>> out;
    detail::collectEntries<R, R>([](R& r) -> R& { return r; }, "", nullptr, out);
    return out;
  }();
  return entries;
}

/// The field of R at `path`; null when none.
template <typename R>
const FieldEntry<R>* findFieldEntry(const std::string& path) {
  for (const auto& e : fieldEntries<R>())
    if (e.path == path) return &e;
  return nullptr;
}

/// Sets the field at `path` of `options` to `value`; std::invalid_argument naming `name` (the
/// path when empty) when no field has that path, or the value is not of the field's type or is
/// out of its bounds. The struct's validate() checks what involves several fields.
template <typename R>
void setField(R& options, const std::string& path, const FieldValue& value, const std::string& name = "") {
  const FieldEntry<R>* e = findFieldEntry<R>(path);
  if (!e) throw std::invalid_argument((name.empty() ? path : name) + ": no such setting");
  e->set(options, value, name.empty() ? path : name);
}

/// Every field's value, by path, in table order (what --show-options prints).
template <typename R>
std::vector<std::pair<std::string, FieldValue>> fieldValues(const R& options) {
  std::vector<std::pair<std::string, FieldValue>> out;
  for (const auto& e : fieldEntries<R>()) out.emplace_back(e.path, e.get(options));
  return out;
}

}  // namespace radar_ndt

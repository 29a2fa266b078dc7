#pragma once
// Errors for bad input. Every settings struct is validated when an object is created;
// a bad value raises InvalidSetting naming the field, the value and what is allowed.

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace shore {

/// Thrown when a setting or an input is out of its allowed range. what() reads like
/// "water.Settings.mass_kg = -1: must be > 0".
class InvalidSetting : public std::invalid_argument {
 public:
  InvalidSetting(const std::string& field, const std::string& value, const std::string& allowed)
      : std::invalid_argument(field + " = " + value + ": " + allowed), field_(field) {}
  /// The offending field's full name.
  [[nodiscard]] const std::string& field() const noexcept { return field_; }

 private:
  std::string field_;
};

/// Thrown when a file cannot be read or written or is not what it claims to be.
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace detail {
template <class T>
std::string to_text(const T& v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}
}  // namespace detail

/// Checks lo < value <= hi style ranges with readable messages. All checks reject NaN.
struct Check {
  std::string prefix;  ///< e.g. "terrain.Material" (prepended to field names)

  [[nodiscard]] std::string name(const char* field) const {
    return prefix.empty() ? std::string(field) : prefix + "." + field;
  }
  template <class T>
  void finite(const char* field, T v) const {
    if (!std::isfinite(static_cast<double>(v))) throw InvalidSetting(name(field), detail::to_text(v), "must be finite");
  }
  template <class T>
  void positive(const char* field, T v) const {
    if (!(v > T(0)) || !std::isfinite(static_cast<double>(v)))
      throw InvalidSetting(name(field), detail::to_text(v), "must be finite and > 0");
  }
  template <class T>
  void non_negative(const char* field, T v) const {
    if (!(v >= T(0)) || !std::isfinite(static_cast<double>(v)))
      throw InvalidSetting(name(field), detail::to_text(v), "must be finite and >= 0");
  }
  /// lo <= v <= hi
  template <class T>
  void in_closed(const char* field, T v, T lo, T hi) const {
    if (!(v >= lo && v <= hi))
      throw InvalidSetting(name(field), detail::to_text(v),
                           "must be in [" + detail::to_text(lo) + ", " + detail::to_text(hi) + "]");
  }
  /// lo < v <= hi
  template <class T>
  void in_left_open(const char* field, T v, T lo, T hi) const {
    if (!(v > lo && v <= hi))
      throw InvalidSetting(name(field), detail::to_text(v),
                           "must be in (" + detail::to_text(lo) + ", " + detail::to_text(hi) + "]");
  }
  /// v >= lo (integers)
  template <class T>
  void at_least(const char* field, T v, T lo) const {
    if (!(v >= lo)) throw InvalidSetting(name(field), detail::to_text(v), "must be >= " + detail::to_text(lo));
  }
};

}  // namespace shore

#pragma once
/// The one format of every parameter struct's validate() error: "<field> = <value>: must be <constraint>",
/// so a user reads which field, which value and which constraint at once.

#include <cmath>
#include <sstream>
#include <string>

namespace tread_wear {

/// Writes the message to *error when error is not null; always returns false (so `return failValidation(...)`).
template <typename T>
bool failValidation(std::string* error, const std::string& field, const T& value, const std::string& constraint) {
  if (error != nullptr) {
    std::ostringstream msg;
    msg.precision(10);
    msg << field << " = " << value << ": must be " << constraint;
    *error = msg.str();
  }
  return false;
}

/// A value as a user typed it, for messages: full precision, and NaN without the sign bit glibc prints ("-nan"
/// means nothing to a user).
inline std::string valueText(double v) {
  if (std::isnan(v)) return "nan";
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

}  // namespace tread_wear

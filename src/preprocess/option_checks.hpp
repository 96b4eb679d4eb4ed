#pragma once
// Option checks shared by the filters' validate() functions: every message
// names the options struct, the field, the value and the allowed range.
#include <cmath>
#include <sstream>
#include <string>

#include "stridemap/core/error.hpp"

namespace stridemap::detail {

inline constexpr double degrees_per_radian = 180.0 / 3.14159265358979323846;

/// Throws unless lower (<= or <) value (<= or <) upper.
inline void require_in_range(const char* owner, const char* field, double value, double lower,
                             bool lower_inclusive, double upper, bool upper_inclusive,
                             const char* unit = "") {
  const bool above = lower_inclusive ? value >= lower : value > lower;
  const bool below = upper_inclusive ? value <= upper : value < upper;
  if (std::isnan(value) || !above || !below) {
    std::ostringstream message;
    message << owner << ": " << field << " is " << value << unit << "; it must be in "
            << (lower_inclusive ? "[" : "(") << lower << unit << ", " << upper << unit
            << (upper_inclusive ? "]" : ")");
    throw InputError(message.str());
  }
}

/// The same for an angle option held in radians, reported in degrees.
inline void require_angle_in_range(const char* owner, const char* field, double value_rad,
                                   double lower_deg, bool lower_inclusive, double upper_deg,
                                   bool upper_inclusive) {
  require_in_range(owner, field, value_rad * degrees_per_radian, lower_deg, lower_inclusive, upper_deg,
                   upper_inclusive, " deg");
}

inline void require_at_least(const char* owner, const char* field, std::size_t value, std::size_t minimum) {
  if (value < minimum) {
    throw InputError(std::string(owner) + ": " + field + " is " + std::to_string(value) +
                     "; it must be at least " + std::to_string(minimum));
  }
}

}  // namespace stridemap::detail

#include "stridemap/sim/scene_problem.hpp"

#include <charconv>
#include <cmath>

namespace stridemap::scene_rules {

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::optional<std::string> finite(double value) {
  if (std::isfinite(value)) return std::nullopt;
  return "expected a finite number, got " + format_number(value);
}

std::optional<std::string> positive(double value) {
  if (std::isfinite(value) && value > 0.0) return std::nullopt;
  return "expected a positive number, got " + format_number(value);
}

std::optional<std::string> non_negative(double value) {
  if (std::isfinite(value) && value >= 0.0) return std::nullopt;
  return "expected a number >= 0, got " + format_number(value);
}

std::optional<std::string> reflectance(double value) {
  if (std::isfinite(value) && value > 0.0 && value <= 1.0) return std::nullopt;
  return "expected a reflectance in (0, 1], got " + format_number(value);
}

}  // namespace stridemap::scene_rules

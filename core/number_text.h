#pragma once
// A double as printf's "%.<significant_digits>g" writes it: 6 digits for names people read
// (the same as "%g"), 17 to round-trip exactly.
#include <cmath>
#include <cstdio>
#include <string>

namespace fovlab {

inline std::string format_number(double value, int significant_digits) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*g", significant_digits, value);
  return text;
}

// An interval as "[lower, upper]", an unbounded end as "(-∞" or "∞)" (UTF-8); "" when either end is
// NaN (not computed).
inline std::string format_interval(double lower, double upper, int significant_digits) {
  if (std::isnan(lower) || std::isnan(upper)) return "";
  const std::string low = std::isinf(lower) ? "(\xE2\x88\x92\xE2\x88\x9E" : "[" + format_number(lower, significant_digits);
  const std::string high = std::isinf(upper) ? "\xE2\x88\x9E)" : format_number(upper, significant_digits) + "]";
  return low + ", " + high;
}

}  // namespace fovlab

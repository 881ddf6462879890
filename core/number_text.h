#pragma once
// A double as printf's "%.<significant_digits>g" writes it: 6 digits for names people read
// (the same as "%g"), 17 to round-trip exactly.
#include <cstdio>
#include <string>

namespace fovlab {

inline std::string format_number(double value, int significant_digits) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*g", significant_digits, value);
  return text;
}

}  // namespace fovlab

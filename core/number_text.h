#pragma once
// A double as printf's "%.<significant_digits>g" writes it: 6 digits for names people read
// (the same as "%g"), 17 to round-trip exactly (exact_number_text: the shortest that does).
#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fovlab {

inline std::string format_number(double value, int significant_digits) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*g", significant_digits, value);
  return text;
}

// The fewest digits that read back as exactly `value`, in %g's notation (std::to_chars, general): a
// number a user gave, at the precision it was given ("0.1", not "0.10000000000000001"; "0.0001";
// "1e+308", not 309 digits). For messages that echo a value, and for commands that must reproduce it.
inline std::string exact_number_text(double value) {
  char text[32];  // the longest such form of a double is 24 characters
  const auto result = std::to_chars(text, text + sizeof text, value, std::chars_format::general);
  return std::string(text, result.ptr);
}
inline std::string exact_number_text(float value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value, std::chars_format::general);
  return std::string(text, result.ptr);
}

// Numbers as exact_number_text writes them, comma-separated: a list flag as given ("--fx 0.05,0.55").
template <typename Number>  // double or float
std::string exact_numbers_text(const std::vector<Number>& values) {
  std::string text;
  for (size_t i = 0; i < values.size(); ++i) {
    if (i) text += ',';
    text += exact_number_text(values[i]);
  }
  return text;
}

// An interval as "[lower, upper]", an unbounded end as "(-∞" or "∞)" (UTF-8); "" when either end is
// NaN (not computed).
inline std::string format_interval(double lower, double upper, int significant_digits) {
  if (std::isnan(lower) || std::isnan(upper)) return "";
  const std::string low =
      std::isinf(lower) ? "(\xE2\x88\x92\xE2\x88\x9E" : "[" + format_number(lower, significant_digits);
  const std::string high = std::isinf(upper) ? "\xE2\x88\x9E)" : format_number(upper, significant_digits) + "]";
  return low + ", " + high;
}

// The whole of `text` as a finite number (std::from_chars: no "+", no spaces, no locale, no "nan"),
// as flags and CSV cells are read.
inline std::optional<double> parse_finite_number(std::string_view text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

}  // namespace fovlab

#include "app/display_flags.h"

#include <cstdio>

#include <charconv>
#include <cmath>

#include "core/input_error.h"

namespace fovlab::app {
namespace {

double positive_number(const std::string& flag, const std::string& text, const std::string& unit) {
  const std::optional<double> value = parse_finite_number(text);
  if (!value || *value <= 0.0) fail_flag(flag, "a positive number of " + unit, text);
  return *value;
}

std::pair<double, double> parse_size_mm(const std::string& text) {
  const std::string expected = "WxH in millimetres, two positive numbers (e.g. 597.7x336.2)";
  const auto parts = split_pair(text, "xX");
  if (!parts) fail_flag("--size-mm", expected, text);
  const std::optional<double> width = parse_finite_number(parts->first);
  const std::optional<double> height = parse_finite_number(parts->second);
  if (!width || !height || *width <= 0.0 || *height <= 0.0) fail_flag("--size-mm", expected, text);
  return {*width, *height};
}

}  // namespace

[[noreturn]] void fail_flag(const std::string& flag, const std::string& expected, const std::string& got) {
  throw InputError(flag + ": expected " + expected + ", got \"" + got + "\"");
}

std::optional<std::pair<std::string_view, std::string_view>> split_pair(std::string_view text,
                                                                        std::string_view separators) {
  const size_t at = text.find_first_of(separators);
  if (at == std::string_view::npos || text.find_first_of(separators, at + 1) != std::string_view::npos)
    return std::nullopt;
  return std::make_pair(text.substr(0, at), text.substr(at + 1));
}

void add_display_flags(CLI::App& command, DisplayFlags& flags, bool required) {
  command.add_option("--diagonal-in", flags.diagonal_in, "Display diagonal in inches (square pixels)");
  command.add_option("--size-mm", flags.size_mm, "Display width x height in mm, e.g. 597.7x336.2");
  CLI::Option* distance =
      command.add_option("--distance-mm", flags.distance_mm, "Viewing distance in mm, eye to the display's centre");
  if (required) distance->required();
  command.add_option("--gaze", flags.gaze, "Gaze point X,Y in pixels (default: the centre, W/2,H/2)");
}

std::string default_to_fpt_study_display(DisplayFlags& flags) {
  std::string assumed;
  if (flags.diagonal_in.empty() && flags.size_mm.empty()) {
    flags.diagonal_in = "27";
    assumed = "Polychronakis et al. 2021's 27-inch monitor";
  }
  if (flags.distance_mm.empty()) {
    flags.distance_mm = "500";
    assumed += std::string(assumed.empty() ? "" : " ") + "at 500 mm";
  }
  return assumed;
}

std::string display_line(const DisplayGeometry& display, const std::string& assumed) {
  char text[160];
  std::snprintf(text, sizeof text, "display %dx%d px, %.1fx%.1f mm at %g mm, %.1f px/deg at the centre",
                display.width_px, display.height_px, display.width_mm, display.height_mm, display.viewing_distance_mm,
                display.pixels_per_degree_at_centre());
  std::string line = text;
  if (!assumed.empty()) line += " (assumed: " + assumed + "; set --diagonal-in or --size-mm, and --distance-mm)";
  return line;
}

bool has_display(const DisplayFlags& flags) {
  return !flags.diagonal_in.empty() || !flags.size_mm.empty() || !flags.distance_mm.empty();
}

DisplayGeometry parse_display(const DisplayFlags& flags, int width_px, int height_px) {
  const bool has_diagonal = !flags.diagonal_in.empty();
  const bool has_size = !flags.size_mm.empty();
  if (has_diagonal == has_size) {
    throw InputError(std::string("--diagonal-in, --size-mm: expected exactly one of them (the display's diagonal in "
                                 "inches, or its width x height in mm), got ") +
                     (has_diagonal ? "both" : "neither"));
  }
  if (flags.distance_mm.empty()) throw InputError("--distance-mm: expected the viewing distance in mm, got none");
  const double distance_mm = positive_number("--distance-mm", flags.distance_mm, "millimetres");
  if (has_diagonal)
    return display_from_diagonal(width_px, height_px, positive_number("--diagonal-in", flags.diagonal_in, "inches"),
                                 distance_mm);
  const auto [width_mm, height_mm] = parse_size_mm(flags.size_mm);
  return display_from_size(width_px, height_px, width_mm, height_mm, distance_mm);
}

std::pair<double, double> parse_gaze(const std::string& text, int width_px, int height_px) {
  if (text.empty()) return {width_px / 2.0, height_px / 2.0};
  const std::string expected = "X,Y in pixels, or in percent of the frame with a trailing % (e.g. 960,540 or 50%,50%)";
  const auto parts = split_pair(text, ",");
  if (!parts) fail_flag("--gaze", expected, text);
  const auto coordinate = [&](std::string_view part, int frame_px) {
    const bool percent = !part.empty() && part.back() == '%';
    const std::optional<double> value = parse_finite_number(percent ? part.substr(0, part.size() - 1) : part);
    if (!value) fail_flag("--gaze", expected, text);
    return percent ? *value / 100.0 * frame_px : *value;
  };
  return {coordinate(parts->first, width_px), coordinate(parts->second, height_px)};
}

}  // namespace fovlab::app

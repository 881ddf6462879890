#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/number_text.h"
#include "core/toml_fields.h"
#include "study/config/config_reading.h"
#include "study/config/study_config.h"
#include "study/stimulus/render_method.h"

namespace fovlab::config_detail {

void read_display(const TomlFields& fields, DisplayConfig& display) {
  const std::string kind = fields.string("kind", "window");
  if (kind == "openxr") {
    display.kind = DisplayKind::openxr;
    read_headset_display(fields, display);  // headset_display_config.cpp
    return;
  }
  if (kind != "window")
    fields.fail("kind",
                "expected \"window\" (a desktop window, the default) or \"openxr\" (a headset, docs/hmd.md), "
                "got \"" +
                    kind + "\"");
  refuse_headset_keys(fields);
  display.width_px = bounded_integer(fields, "width_px", std::nullopt, 8, 16384);
  display.height_px = bounded_integer(fields, "height_px", std::nullopt, 8, 16384);
  display.refresh_hz = fields.number("refresh_hz", 60.0);
  check_range(fields, "refresh_hz", display.refresh_hz, 1.0, 1000.0);
  const bool has_diagonal = fields.has("diagonal_in");
  const bool has_size = fields.has("width_mm") || fields.has("height_mm");
  if (has_diagonal == has_size)
    fields.fail("", "expected either diagonal_in or width_mm and height_mm (the visible area), not both or neither");
  if (has_diagonal) {
    const double diagonal_in = fields.number("diagonal_in");
    check_range(fields, "diagonal_in", diagonal_in, 0.1, 10000.0);
    // Square pixels: the visible area has the resolution's aspect ratio.
    const double diagonal_px = std::hypot(double(display.width_px), double(display.height_px));
    display.width_mm = diagonal_in * 25.4 * display.width_px / diagonal_px;
    display.height_mm = diagonal_in * 25.4 * display.height_px / diagonal_px;
  } else {
    display.width_mm = fields.number("width_mm");
    check_range(fields, "width_mm", display.width_mm, 1.0, 1e6);
    display.height_mm = fields.number("height_mm");
    check_range(fields, "height_mm", display.height_mm, 1.0, 1e6);
  }
  display.viewing_distance_mm = fields.number("viewing_distance_mm");
  check_range(fields, "viewing_distance_mm", display.viewing_distance_mm, 1.0, 1e6);
  display.fullscreen = fields.boolean("fullscreen", false);
  fields.finish();
}

// [gaze] require = "tracker" or ["tracker", "trace"]: the kinds of source a session may use.
void read_gaze(const TomlFields& fields, GazeConfig& gaze) {
  const std::string expected =
      "expected a gaze source kind (tracker, trace, synthetic or mouse) or a non-empty array of them";
  if (!fields.has("require")) fields.fail("require", "missing: " + expected + " (or no [gaze] table)");
  const toml::node& node = *fields.raw().get("require");
  gaze.require_line = static_cast<int>(node.source().begin.line);
  std::vector<std::string> names;
  if (node.is_string()) names.push_back(fields.string("require"));
  else if (node.is_array()) names = fields.strings("require");
  else fields.fail("require", expected);
  for (const std::string& name : names) {
    const std::optional<GazeSourceKind> kind = parse_gaze_source_kind(name);
    if (!kind)
      fields.fail("require", expected + ", got \"" + name + "\"" +
                                 (name == "pupil" ? " (Pupil Core is the kind \"tracker\")" : ""));
    if (gaze.allows(*kind)) fields.fail("require", "\"" + name + "\" given twice; expected each kind once");
    gaze.require.push_back(*kind);
  }
  fields.finish();
}

void read_validation(const TomlFields& fields, const DisplayConfig& display, ValidationConfig& validation) {
  validation.enabled = true;
  validation.targets = bounded_integer(fields, "targets", validation.targets, 5, 9);
  if (validation.targets != 5 && validation.targets != 9) fields.fail("targets", "expected 5 or 9");
  validation.target_offset_deg = bounded_number(fields, "target_offset_deg", validation.target_offset_deg, 0.5, 40.0);
  validation.target_radius_deg = bounded_number(fields, "target_radius_deg", validation.target_radius_deg, 0.05, 2.0);
  validation.target_s = bounded_number(fields, "target_s", validation.target_s, 0.2, 10.0);
  validation.settle_s = bounded_number(fields, "settle_s", validation.settle_s, 0.0, validation.target_s - 0.1);
  validation.max_accuracy_deg = bounded_number(fields, "max_accuracy_deg", validation.max_accuracy_deg, 0.01, 10.0);
  validation.max_precision_deg = bounded_number(fields, "max_precision_deg", validation.max_precision_deg, 0.001, 10.0);
  validation.max_attempts = bounded_integer(fields, "max_attempts", validation.max_attempts, 1, 20);
  validation.after_breaks = fields.boolean("after_breaks", validation.after_breaks);
  // At least three refreshes measured a target (two successive samples give a precision).
  const int refreshes = static_cast<int>(std::floor(validation.target_s * display.refresh_hz + 1e-9));
  const int first = std::max(1, static_cast<int>(std::ceil(validation.settle_s * display.refresh_hz - 1e-9)));
  if (refreshes - first + 1 < 3)
    fields.fail("settle_s", "expected target_s - settle_s to hold at least 3 refreshes at " +
                                format_number(display.refresh_hz, 6) + " Hz (each target is measured on them)");
  if (display.kind == DisplayKind::openxr) {
    check_validation_targets_in_each_eye(fields, display.headset, validation);
    fields.finish();
    return;
  }
  // Every target, disk included, on the screen.
  const double radius_px = validation_target_radius_px(display, validation);
  for (const auto& [x_px, y_px] : validation_targets_px(display, validation)) {
    if (x_px - radius_px < 0 || x_px + radius_px > display.width_px || y_px - radius_px < 0 ||
        y_px + radius_px > display.height_px)
      fields.fail("target_offset_deg", "expected targets on the screen: at " +
                                           format_number(validation.target_offset_deg, 6) +
                                           " deg the outer ones fall off this display (" +
                                           std::to_string(display.width_px) + "x" + std::to_string(display.height_px) +
                                           " px at " + format_number(display.viewing_distance_mm, 6) + " mm)");
  }
  fields.finish();
}

}  // namespace fovlab::config_detail

namespace fovlab {

namespace {
double degrees_to_px(const DisplayConfig& display, double degrees, double pitch_mm) {
  return display.viewing_distance_mm * std::tan(degrees * std::numbers::pi / 180.0) / pitch_mm;
}
}  // namespace

std::vector<std::pair<double, double>> validation_targets_px(const DisplayConfig& display,
                                                             const ValidationConfig& validation) {
  const double centre_x = 0.5 * display.width_px, centre_y = 0.5 * display.height_px;
  const double dx = degrees_to_px(display, validation.target_offset_deg, display.width_mm / display.width_px);
  const double dy = degrees_to_px(display, validation.target_offset_deg, display.height_mm / display.height_px);
  std::vector<std::pair<double, double>> targets;
  for (int row = -1; row <= 1; ++row)
    for (int column = -1; column <= 1; ++column)
      if (validation.targets == 9 || (row == 0) == (column == 0))  // 5: centre and corners
        targets.emplace_back(centre_x + column * dx, centre_y + row * dy);
  return targets;
}

double validation_target_radius_px(const DisplayConfig& display, const ValidationConfig& validation) {
  return std::max(2.0, degrees_to_px(display, validation.target_radius_deg, display.width_mm / display.width_px));
}

const char* gaze_source_kind_name(GazeSourceKind kind) {
  switch (kind) {
    case GazeSourceKind::tracker:
      return "tracker";
    case GazeSourceKind::trace:
      return "trace";
    case GazeSourceKind::synthetic:
      return "synthetic";
    case GazeSourceKind::mouse:
      return "mouse";
  }
  return "";
}

std::optional<GazeSourceKind> parse_gaze_source_kind(const std::string& name) {
  for (GazeSourceKind kind :
       {GazeSourceKind::tracker, GazeSourceKind::trace, GazeSourceKind::synthetic, GazeSourceKind::mouse})
    if (name == gaze_source_kind_name(kind)) return kind;
  return std::nullopt;
}

std::optional<GazeSourceKind> gaze_source_kind_of_spec(const std::string& spec) {
  const auto named = [&](const std::string& prefix) {
    return spec == prefix || spec.rfind(prefix + ":", 0) == 0 || spec.rfind(prefix + ",", 0) == 0;
  };
  if (spec == "mouse") return GazeSourceKind::mouse;
  if (spec.rfind("trace:", 0) == 0) return GazeSourceKind::trace;
  if (named("synthetic")) return GazeSourceKind::synthetic;
  if (named("pupil") || spec == "openxr") return GazeSourceKind::tracker;
  return std::nullopt;
}

bool GazeConfig::allows(GazeSourceKind kind) const {
  return std::find(require.begin(), require.end(), kind) != require.end();
}

std::string GazeConfig::require_text() const {
  std::string text;
  for (size_t i = 0; i < require.size(); ++i)
    text += (i == 0 ? "" : i + 1 == require.size() ? " or " : ", ") + std::string(gaze_source_kind_name(require[i]));
  return text;
}

bool is_gaze_contingent(const StudyConfig& config) {
  return describe(config.stimulus.reference.method).depends_on_gaze ||
         describe(config.stimulus.test.method).depends_on_gaze;
}

}  // namespace fovlab

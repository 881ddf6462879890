#include "app/foveation_flags.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/input_error.h"
#include "core/number_text.h"

namespace fovlab::app {
namespace {

// The names of every value of a choice (its k* array and *_name function), for CLI::IsMember.
template <typename Choices, typename NameOf>
std::vector<std::string> choice_names(const Choices& choices, NameOf name_of) {
  std::vector<std::string> names;
  for (const auto& choice : choices) names.emplace_back(name_of(choice));
  return names;
}

}  // namespace

void add_foveation_flags(CLI::App& command, FoveationFlags& flags, FoveationPoint point) {
  add_display_flags(command, flags.display, false);
  if (point == FoveationPoint::single) {
    command.add_option("--fovea-deg", flags.fovea_deg,
                       "FIPR: foveal eccentricity in degrees (everything traced within)");
    command.add_option("--refresh", flags.refresh, "FIPR: periphery refreshed every 1st, 2nd or 4th frame");
  }
  command.add_option("--outer-periphery-deg", flags.outer_periphery_deg,
                     "FIPR: eccentricity beyond which nothing is traced at the top level (default: none)");
  command.add_option("--periphery-steps", flags.periphery_steps,
                     "FIPR: step budget of pixels outside the mask, traced from the mid depth; 0: mid level's colour");
  command
      .add_option("--periphery-reconstruction", flags.periphery_reconstruction,
                  "FIPR: how --periphery-steps 0 fills pixels from the mid level: bilinear (each mid colour textured "
                  "over a pixel's footprint), catmull-rom (so, and Catmull-Rom), mid-footprint-bilinear (over its own "
                  "footprint, bilinear: every FIPR frame before log schema 5)")
      ->check(CLI::IsMember(choice_names(kPeripheryReconstructions, periphery_reconstruction_name)));
  command
      .add_option("--near-misses", flags.near_misses,
                  "FIPR: where a low or mid ray passed a surface within its pixel's cone: promote (the periphery's "
                  "pixels there traced in full, from in front of it), ignore (the paper's: every FIPR frame before "
                  "log schema 6)")
      ->check(CLI::IsMember(choice_names(kNearMisses, near_misses_name)));
  command.add_option("--blur", flags.blur, "FIPR: masked Gaussian blur, on or off")
      ->check(CLI::IsMember({"on", "off"}));
  command
      .add_option("--combine", flags.combine,
                  "FIPR: acuity and edges combined by max, fovea-or-product, product, acuity")
      ->check(CLI::IsMember({"max", "fovea-or-product", "product", "acuity"}));
  command.add_option("--edge-threshold", flags.edge_threshold,
                     "FIPR: Sobel magnitude of the low-level depth, relative to the depth, that makes an edge");
  command
      .add_option("--edge-depth", flags.edge_depth,
                  "FIPR: the low level's depth the edges are found in: centre-ray (where its centre ray hits; with "
                  "--coarse-test cone marched on from the cone's stop), level (the depth passed on: the cone's stop; "
                  "every FIPR frame before log schema 10)")
      ->check(CLI::IsMember(choice_names(kEdgeDepths, edge_depth_name)));
  command.add_option("--seed", flags.seed, "FIPR: seed of the per-pixel thresholds");
}

std::vector<std::string> given_fipr_only_flags(const CLI::App& command) {
  std::vector<std::string> given;
  for (const CLI::Option* option : command.get_options()) {
    if (option->count() > 0 && option->get_description().rfind("FIPR:", 0) == 0) given.push_back(option->get_name());
  }
  return given;
}

FoveationSettings parse_foveation(const FoveationFlags& flags, int width_px, int height_px) {
  FoveationSettings settings;
  if (has_display(flags.display)) {
    settings.display = parse_display(flags.display, width_px, height_px);
  } else {
    settings.display = display_from_diagonal(width_px, height_px, kDefaultDiagonalIn, kDefaultViewingDistanceMm);
  }
  if (flags.display.gaze == "none") {
    settings.gaze_x_px = settings.gaze_y_px = std::numeric_limits<double>::quiet_NaN();
  } else {
    std::tie(settings.gaze_x_px, settings.gaze_y_px) = parse_gaze(flags.display.gaze, width_px, height_px);
  }
  settings.acuity.fovea_radius_deg = flags.fovea_deg;
  if (!flags.outer_periphery_deg.empty()) {
    const std::optional<double> outer = parse_finite_number(flags.outer_periphery_deg);
    if (!outer) fail_flag("--outer-periphery-deg", "an eccentricity in degrees", flags.outer_periphery_deg);
    settings.acuity.outer_periphery_radius_deg = *outer;
  }
  settings.periphery_refresh = flags.refresh;
  settings.periphery_steps = flags.periphery_steps;
  settings.reconstruction =
      parse_periphery_reconstruction(flags.periphery_reconstruction).value_or(FoveationSettings{}.reconstruction);
  settings.near_misses = parse_near_misses(flags.near_misses).value_or(FoveationSettings{}.near_misses);
  settings.blur = flags.blur == "on";
  settings.combine = parse_mask_combine(flags.combine).value_or(MaskCombine::max);
  settings.edge_threshold = flags.edge_threshold;
  settings.edge_depth = parse_edge_depth(flags.edge_depth).value_or(FoveationSettings{}.edge_depth);
  settings.seed = flags.seed;
  return settings;
}

std::string display_flags_text(const DisplayFlags& display) {
  std::string text;
  const auto add = [&](const char* flag, const std::string& value) {
    if (!value.empty()) text += std::string(text.empty() ? "" : " ") + flag + " " + value;
  };
  if (has_display(display)) {
    add("--diagonal-in", display.diagonal_in);
    add("--size-mm", display.size_mm);
    add("--distance-mm", display.distance_mm);
  } else {
    add("--diagonal-in", format_number(kDefaultDiagonalIn, 6));
    add("--distance-mm", format_number(kDefaultViewingDistanceMm, 6));
  }
  add("--gaze", display.gaze);
  return text;
}

std::string foveation_flags_text(const FoveationFlags& flags) {
  std::string text = display_flags_text(flags.display);
  const auto add = [&](const char* flag, const std::string& value) {
    if (!value.empty()) text += std::string(" ") + flag + " " + value;
  };
  add("--outer-periphery-deg", flags.outer_periphery_deg);
  add("--periphery-steps", std::to_string(flags.periphery_steps));
  add("--periphery-reconstruction", flags.periphery_reconstruction);
  add("--near-misses", flags.near_misses);
  add("--blur", flags.blur);
  add("--combine", flags.combine);
  add("--edge-threshold", format_number(flags.edge_threshold, 6));
  // Only where it is not the default (the reports of earlier builds had no such flag).
  if (flags.edge_depth != edge_depth_name(FoveationSettings{}.edge_depth)) add("--edge-depth", flags.edge_depth);
  add("--seed", std::to_string(flags.seed));
  return text;
}

}  // namespace fovlab::app

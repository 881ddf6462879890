#pragma once
// The FIPR flags of `render` and `bench`: display and gaze (app/display_flags.h), fovea, outer
// periphery, periphery refresh and reconstruction, blur, how edges and acuity combine, edge
// threshold, seed. Without display flags FIPR assumes a 24-inch display at 600 mm (docs/foveation.md).
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/display_flags.h"
#include "renderer/sphere_tracing/sphere_tracer.h"

namespace fovlab::app {

constexpr double kDefaultDiagonalIn = 24.0;
constexpr double kDefaultViewingDistanceMm = 600.0;

struct FoveationFlags {
  DisplayFlags display;
  double fovea_deg = AcuityModel{}.fovea_radius_deg;
  std::string outer_periphery_deg;  // empty: none
  int refresh = 1;
  int periphery_steps = FoveationSettings{}.periphery_steps;
  std::string periphery_reconstruction = periphery_reconstruction_name(FoveationSettings{}.reconstruction);
  std::string near_misses = near_misses_name(FoveationSettings{}.near_misses);
  std::string blur = "off";
  std::string combine = "max";
  float edge_threshold = FoveationSettings{}.edge_threshold;
  std::string edge_depth = edge_depth_name(FoveationSettings{}.edge_depth);
  uint32_t seed = 0;
};

// `single`: --fovea-deg and --refresh take one value each (render); `swept`: the command adds its
// own lists of them (bench).
enum class FoveationPoint { single, swept };
void add_foveation_flags(CLI::App& command, FoveationFlags& flags, FoveationPoint point);
// The FIPR-only flags given on a command line (their descriptions start with "FIPR:"; the display
// flags serve other methods too), so a command can refuse them without --method fipr.
std::vector<std::string> given_fipr_only_flags(const CLI::App& command);

// Settings for a width_px x height_px frame; --gaze none means no gaze sample (every pixel traced in
// full). InputError naming the flag on bad values.
FoveationSettings parse_foveation(const FoveationFlags& flags, int width_px, int height_px);
// The display flags as they reproduce the display assumed (the default one spelled out), and --gaze.
std::string display_flags_text(const DisplayFlags& display);
// The flags that reproduce these settings, for bench reports ("--diagonal-in 24 --distance-mm 600 ...").
std::string foveation_flags_text(const FoveationFlags& flags);

}  // namespace fovlab::app

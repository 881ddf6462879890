#include "renderer/sphere_tracing/foveation_json.h"

#include <cmath>

#include "foveation/foveation_mask.h"

namespace fovlab {

nlohmann::json display_json(const DisplayGeometry& display) {
  return {{"width_mm", display.width_mm},
          {"height_mm", display.height_mm},
          {"viewing_distance_mm", display.viewing_distance_mm},
          {"pixels_per_degree_at_centre", display.pixels_per_degree_at_centre()}};
}

nlohmann::json foveation_json(const FoveationSettings& f, const FoveationStats& stats, double pixels) {
  const bool has_gaze = std::isfinite(f.gaze_x_px) && std::isfinite(f.gaze_y_px);
  return {
      {"gaze_px", has_gaze ? nlohmann::json::array({f.gaze_x_px, f.gaze_y_px}) : nlohmann::json(nullptr)},
      {"fovea_deg", f.acuity.fovea_radius_deg},
      {"outer_periphery_deg", std::isfinite(f.acuity.outer_periphery_radius_deg)
                                  ? nlohmann::json(f.acuity.outer_periphery_radius_deg)
                                  : nlohmann::json(nullptr)},
      {"combine", mask_combine_name(f.combine)},
      {"edge_threshold", f.edge_threshold},
      {"periphery_refresh", f.periphery_refresh},
      {"periphery_steps", f.periphery_steps},
      {"periphery_reconstruction", periphery_reconstruction_name(f.reconstruction)},
      {"near_misses", near_misses_name(f.near_misses)},
      {"blur", f.blur},
      {"seed", f.seed},
      {"frame_index", f.frame_index},
      {"display", display_json(f.display)},
      {"top_level_share", double(stats.masked_pixels) / pixels},
      {"refreshed_share", double(stats.refreshed_pixels) / pixels},
      {"kept_share", double(stats.kept_pixels) / pixels},
  };
}

}  // namespace fovlab

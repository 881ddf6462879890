#include "app/render_outputs.h"

#include <algorithm>
#include <cctype>

#include "core/colour.h"
#include "core/image_io.h"
#include "renderer/sphere_tracing/step_heatmap.h"

namespace fovlab::app {

namespace {
bool is_exr(const std::filesystem::path& path) { return lower_extension(path) == ".exr"; }
}  // namespace

void write_colour(const std::filesystem::path& path, const Image& colour_linear) {
  write_image(path, is_exr(path) ? colour_linear : encode_srgb(colour_linear));
}

Image display_image(const SphereTraceResult& result) { return encode_srgb(result.colour_linear); }

void write_step_heatmap(const std::filesystem::path& path, const SphereTraceResult& result,
                        const SphereTraceSettings& settings) {
  write_image(path, step_heatmap(result.steps_per_pixel, settings.samples_per_pixel, settings.max_steps));
}

nlohmann::json stats_json(const std::string& scene_name, const SphereTraceSettings& settings,
                          const SphereTraceResult& result, double wall_ms, const vk::Context& context) {
  nlohmann::json passes = nlohmann::json::object();
  for (const vk::PassTime& pass : result.passes) passes[pass.name] = pass.gpu_ms;
  nlohmann::json levels = nlohmann::json::array();
  for (const PyramidLevelStats& level : result.levels) {
    levels.push_back({{"width", level.width}, {"height", level.height}, {"scale", level.scale}, {"steps", level.steps}});
  }
  nlohmann::json stats = {
      {"scene", scene_name},
      {"method", method_name(settings.method)},
      {"width", settings.width},
      {"height", settings.height},
      {"spp", settings.samples_per_pixel},
      {"time_s", settings.time_s},
      {"max_steps", settings.max_steps},
      {"hit_threshold", settings.hit_threshold},
      {"total_steps", result.total_steps},
      {"steps_per_pixel", result.mean_steps_per_pixel()},
      {"steps_per_sample", result.mean_steps_per_pixel() / settings.samples_per_pixel},
      {"capped_rays", result.capped_rays},
      {"restarted_rays", result.restarted_rays},
      {"levels", levels},
      {"gpu_ms", {{"total", result.gpu_ms}, {"passes", passes}, {"timestamps", context.timestamp_period_ns > 0}}},
      {"wall_ms", wall_ms},
      {"device", context.description.name},
  };
  if (settings.method == TraceMethod::inverted_pyramid) {
    stats["pyramid_levels"] = settings.pyramid_levels;
    stats["min_filter_size"] = settings.min_filter_size;
  }
  return stats;
}

}  // namespace fovlab::app

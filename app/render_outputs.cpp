#include "app/render_outputs.h"

#include <cmath>

#include <algorithm>
#include <cctype>

#include "core/colour.h"
#include "core/image_io.h"
#include "renderer/sphere_tracing/foveation_json.h"
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
    levels.push_back({{"width", level.width},
                      {"height", level.height},
                      {"scale", level.scale},
                      {"steps", level.steps},
                      {"traced_share", level.traced_share()},
                      {"shaded_share", double(level.shaded_pixels) / (double(level.width) * double(level.height))}});
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
  if (settings.sampling) {
    const SamplingMap& map = *settings.sampling;
    const double pixels = double(settings.width) * double(settings.height);
    stats["method"] = sampling_model_name(model_of(map));
    stats["sampling"] = {
        {"model", sampling_model_name(model_of(map))},
        {"shaded_samples", result.shaded_samples},
        {"shaded_share", double(result.shaded_samples) / pixels},
        {"theoretical_speedup", theoretical_speedup(map)},
        {"effective_speedup", pixels / double(std::max<uint64_t>(1, result.shaded_samples))},
        {"mean_density", mean_density(map)},
    };
  } else if (settings.method != TraceMethod::ground_truth) {
    stats["pyramid_levels"] = settings.pyramid_levels;
    stats["min_filter_size"] = settings.min_filter_size;
    stats["coarse_test"] = coarse_test_name(settings.coarse_test);
    if (settings.method == TraceMethod::inverted_pyramid)
      stats["full_resolution_depth"] = settings.full_resolution_depth;
  }
  if (settings.method == TraceMethod::foveated_pyramid) {
    stats["foveation"] = foveation_json(settings.foveation, result.foveation,
                                        double(settings.width) * double(settings.height));
  }
  return stats;
}

namespace {
float density_grey(double samples_per_pixel) {
  if (!(samples_per_pixel > 0)) return 0.0f;
  return static_cast<float>(std::clamp(1.0 + std::log2(samples_per_pixel) / 8.0, 0.0, 1.0));
}
}  // namespace

Image density_image(const SamplingMap& map) {
  Image image(screen_width_px(map), screen_height_px(map), 1);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) image.at(x, y, 0) = density_grey(density(map, x + 0.5, y + 0.5));
  return image;
}

Image samples_per_pixel_image(const Image& samples) {
  Image image(samples.width, samples.height, 1);
  for (size_t p = 0; p < samples.pixels.size(); ++p) image.pixels[p] = density_grey(samples.pixels[p]);
  return image;
}

}  // namespace fovlab::app

#pragma once
// What `render` and `bench` write about a frame: images, step heat maps, statistics as JSON.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/vk/context.h"

namespace fovlab::app {

// PNG and other 8-bit formats get sRGB-encoded colour; EXR keeps linear light.
void write_colour(const std::filesystem::path& path, const Image& colour_linear);

// Display image (sRGB-encoded) of a render, as the metrics compare it.
Image display_image(const SphereTraceResult& result);

// A sampling model's density (foveation/sampling_map.h density()) as a grey image: white at one
// sample a pixel or more, black at 1/256 or less, log2 in between (each stop 1/8 of the range).
Image density_image(const SamplingMap& map);
// The samples each pixel holds (SphereTraceResult::mask of a sampling model) on the same scale.
Image samples_per_pixel_image(const Image& samples);

void write_step_heatmap(const std::filesystem::path& path, const SphereTraceResult& result,
                        const SphereTraceSettings& settings);

nlohmann::json stats_json(const std::string& scene_name, const SphereTraceSettings& settings,
                          const SphereTraceResult& result, double wall_ms, const vk::Context& context);

}  // namespace fovlab::app

#pragma once
// What `render` and `bench` write about a frame: images, step heat maps, statistics as JSON.
#include <filesystem>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/vk/context.h"

namespace fovlab::app {

// PNG and other 8-bit formats get sRGB-encoded colour; EXR keeps linear light.
void write_colour(const std::filesystem::path& path, const Image& colour_linear);

// Display image (sRGB-encoded) of a render, as the metrics compare it.
Image display_image(const SphereTraceResult& result);

void write_step_heatmap(const std::filesystem::path& path, const SphereTraceResult& result,
                        const SphereTraceSettings& settings);

nlohmann::json stats_json(const std::string& scene_name, const SphereTraceSettings& settings,
                          const SphereTraceResult& result, double wall_ms, const vk::Context& context);

// Exits with an internal error when the validation layer reported anything: a clean run is part of
// the contract (the tests run with validation on).
void fail_on_validation_messages(const vk::Context& context);

// Context options from --device and the validation default.
vk::ContextOptions context_options(const std::string& device_selector);

}  // namespace fovlab::app

namespace fovlab::app {
// --levels, --min-filter, --max-steps, --hit-threshold, --time: shared by render and bench.
void add_trace_options(CLI::App& command, SphereTraceSettings& settings);
}  // namespace fovlab::app

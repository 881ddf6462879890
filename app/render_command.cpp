// fovlab render: one frame of a scene with ground truth or the inverted pyramid.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app/cli_support.h"
#include "app/commands.h"
#include "app/render_outputs.h"
#include "core/atomic_file.h"
#include "core/image_io.h"
#include "renderer/scene/scene_source.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/vk/context.h"

namespace fovlab::app {

namespace {
struct RenderOptions {
  std::string scene;
  std::string method = "gt";
  SphereTraceSettings settings;
  std::filesystem::path out;
  std::filesystem::path steps_out;
  std::filesystem::path stats_json;
  std::string device;
};

void run_render(const RenderOptions& options) {
  SphereTraceSettings settings = options.settings;
  settings.method = options.method == "ipr" ? TraceMethod::inverted_pyramid : TraceMethod::ground_truth;
  validate(settings);
  check_image_output_path(options.out, "--out");
  if (!options.steps_out.empty()) check_image_output_path(options.steps_out, "--steps-out");
  if (!options.stats_json.empty()) check_output_path(options.stats_json, "--stats-json");

  const SceneSource scene = load_scene(options.scene);
  vk::Context context(context_options(options.device));
  SphereTracer tracer(context, scene);
  const auto started = std::chrono::steady_clock::now();
  const SphereTraceResult result = tracer.render(settings);
  const double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  fail_on_validation_messages(context);

  write_colour(options.out, result.colour_linear);
  if (!options.steps_out.empty()) write_step_heatmap(options.steps_out, result, settings);
  const nlohmann::json stats = stats_json(scene.name, settings, result, wall_ms, context);
  if (!options.stats_json.empty()) write_text_atomically(options.stats_json, stats.dump(2) + "\n");
  std::printf("%s %s %dx%d spp %d: %.2f ms GPU, %.2f steps/pixel, %llu capped rays -> %s\n", scene.name.c_str(),
              method_name(settings.method), settings.width, settings.height, settings.samples_per_pixel,
              result.gpu_ms, stats["steps_per_pixel"].get<double>(),
              static_cast<unsigned long long>(result.capped_rays), options.out.c_str());
}
}  // namespace

void add_render_command(CLI::App& app) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* command = app.add_subcommand("render", "Render one frame of a scene to an image");
  command->add_option("--scene", options->scene, "Built-in scene name or path to a .glsl scene file")->required();
  command->add_option("--method", options->method, "gt (ground truth) or ipr (inverted pyramid)")
      ->check(CLI::IsMember({"gt", "ipr"}));
  command->add_option("--width", options->settings.width, "Frame width in pixels")->required();
  command->add_option("--height", options->settings.height, "Frame height in pixels")->required();
  command->add_option("--spp", options->settings.samples_per_pixel, "Samples per pixel: 1, 4 or 16");
  command->add_option("--out", options->out, "Image to write (.png: sRGB, .exr: linear)")->required();
  command->add_option("--steps-out", options->steps_out, "Step-count heat map to write (blue 1 step, red cap)");
  command->add_option("--stats-json", options->stats_json, "Statistics of the frame as JSON");
  command->add_option("--device", options->device, "Vulkan device: index or part of its name (fovlab devices)");
  add_trace_options(*command, options->settings);
  command->callback([options] { run_render(*options); });
}

}  // namespace fovlab::app

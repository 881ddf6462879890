// fovlab render: a frame of a scene with ground truth, the inverted pyramid or its foveated form
// (FIPR; --frames N renders a sequence, so the periphery refresh reuses earlier frames), or one of
// Ye et al. 2022's sampling models (rmfr, hyperbolic, linear, kfr), which shade only their samples; with
// --method volume or fvolume, Bruder et al. 2019's volume raycaster (app/render_volume.h).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "app/cli_support.h"
#include "app/commands.h"
#include "app/foveation_flags.h"
#include "app/output_options.h"
#include "app/render_outputs.h"
#include "app/render_volume.h"
#include "app/sampling_flags.h"
#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "core/memory_budget.h"
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
  std::filesystem::path mask_out;
  std::filesystem::path density_out;
  std::string device;
  SamplingSettings sampling;
  std::vector<std::string> sampling_flags_given;
  FoveationFlags foveation;
  std::vector<std::string> fipr_flags_given;
  PyramidFlagsGiven pyramid_flags_given;  // --min-filter, --coarse-test: else the method's own defaults
  int frames = 1;
  double frame_rate_hz = 60.0;
  VolumeRenderOptions volume;  // --method volume, fvolume: the volume-only flags
};

// The volume raycaster: the flags both renderers share, then its own; the sphere tracer's are refused.
void run_volume_render(const RenderOptions& options, const CLI::App& command) {
  for (const char* flag :
       {"--spp", "--steps-out", "--density-out", "--levels", "--min-filter", "--max-steps", "--hit-threshold"})
    if (command.get_option(flag)->count() > 0)
      throw InputError(std::string(flag) + ": the sphere tracer's; --method " + options.method + " does not use it");
  if (!options.fipr_flags_given.empty())
    throw InputError(options.fipr_flags_given.front() + ": only FIPR uses it; --method " + options.method +
                     " does not");
  if (!options.sampling_flags_given.empty())
    throw InputError(options.sampling_flags_given.front() + ": only the sampling models use it; --method " +
                     options.method + " does not");
  VolumeRenderOptions volume = options.volume;
  volume.scene = options.scene;
  volume.foveated = options.method == "fvolume";
  volume.width_px = options.settings.width;
  volume.height_px = options.settings.height;
  volume.time_s = options.settings.time_s;
  volume.frames = options.frames;
  volume.frame_rate_hz = options.frame_rate_hz;
  volume.display = options.foveation.display;
  volume.device = options.device;
  volume.out = options.out;
  volume.mask_out = options.mask_out;
  volume.stats_json = options.stats_json;
  if (!volume.foveated) {
    for (const char* flag : {"--sigma-deg", "--no-opacity-correction", "--no-smoothing"})
      if (command.get_option(flag)->count() > 0)
        throw InputError(std::string(flag) + ": only fvolume uses it; add --method fvolume");
  }
  run_render_volume(volume);
}

void run_render(const RenderOptions& options) {
  SphereTraceSettings settings = options.settings;
  const std::optional<SamplingModel> model = parse_sampling_model(options.method);
  settings.method =
      model ? TraceMethod::sampling_model : parse_trace_method(options.method).value_or(TraceMethod::ground_truth);
  settings = with_method_pyramid_defaults(settings, settings.method, options.pyramid_flags_given);
  const bool foveated = settings.method == TraceMethod::foveated_pyramid;
  if (foveated || model) settings.foveation = parse_foveation(options.foveation, settings.width, settings.height);
  if (!foveated && !options.fipr_flags_given.empty())
    throw InputError(options.fipr_flags_given.front() + ": only FIPR uses it; add --method fipr");
  if (!model && !options.sampling_flags_given.empty())
    throw InputError(options.sampling_flags_given.front() +
                     ": only the sampling models use it; add --method rmfr, hyperbolic, linear or kfr");
  if (!model && !options.density_out.empty())
    throw InputError(
        "--density-out: only the sampling models (--method rmfr, hyperbolic, linear or kfr) have a sampling density");
  if (model) {
    refuse_flags_unused_by(options.sampling_flags_given, {*model});
    settings.sampling = parse_sampling(*model, options.sampling, settings.foveation);
    settings.sampling_filter = options.sampling.filter;
  }
  validate_trace_flags(settings);
  if (options.frames < 1 || options.frames > 100000)
    throw InputError("--frames " + std::to_string(options.frames) + ": expected 1 to 100000");
  if (!(options.frame_rate_hz > 0.0 && std::isfinite(options.frame_rate_hz)))
    throw InputError("--frame-rate: expected a positive number of frames per second");
  // A frame too large for this machine's memory is refused now, before the scene is compiled.
  check_memory_fits(render_memory_bytes(settings),
                    "--width x --height = " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                        " (--method " + method_name(settings.method) + ")",
                    "lower --width and --height");
  if (!options.mask_out.empty() && !foveated && !model)
    throw InputError(
        "--mask-out: only FIPR and the sampling models have a foveation mask (--method fipr, rmfr, hyperbolic, linear, "
        "kfr)");

  const SceneSource scene = load_scene(options.scene);
  vk::Context context(context_options(options.device));
  SphereTracer tracer(context, scene);
  // Frame k of a sequence is at scene time --time + k / --frame-rate; the last one is written.
  SphereTraceResult result;
  std::vector<double> gpu_ms;
  const auto started = std::chrono::steady_clock::now();
  for (int frame = 0; frame < options.frames; ++frame) {
    SphereTraceSettings frame_settings = settings;
    frame_settings.time_s = static_cast<float>(settings.time_s + frame / options.frame_rate_hz);
    frame_settings.foveation.frame_index = static_cast<uint32_t>(frame);
    result = tracer.render(frame_settings);
    gpu_ms.push_back(result.gpu_ms);
    settings = frame_settings;
  }
  const double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  fail_on_validation_messages(context);

  write_colour(options.out, result.colour_linear);
  if (!options.steps_out.empty()) write_step_heatmap(options.steps_out, result, settings);
  if (!options.mask_out.empty())
    write_image(options.mask_out, model ? samples_per_pixel_image(result.mask) : result.mask);
  if (!options.density_out.empty()) write_image(options.density_out, density_image(*settings.sampling));
  nlohmann::json stats = stats_json(scene.name, settings, result, wall_ms / options.frames, context);
  stats["frames"] = options.frames;
  stats["gpu_ms_per_frame"] = gpu_ms;
  if (!options.stats_json.empty()) write_text_atomically(options.stats_json, stats.dump(2) + "\n");
  std::printf("%s %s %dx%d spp %d: %.2f ms GPU, %.2f steps/pixel, %llu capped rays", scene.name.c_str(),
              model ? sampling_model_name(*model) : method_name(settings.method), settings.width, settings.height,
              settings.samples_per_pixel, result.gpu_ms, stats["steps_per_pixel"].get<double>(),
              static_cast<unsigned long long>(result.capped_rays));
  if (foveated) {
    std::printf(", %.1f %% of pixels traced at the top level, %.1f %% refreshed",
                100.0 * stats["foveation"]["top_level_share"].get<double>(),
                100.0 * stats["foveation"]["refreshed_share"].get<double>());
  }
  if (model)
    std::printf(", %s; %llu samples traced", sampling_summary(*settings.sampling).c_str(),
                static_cast<unsigned long long>(result.shaded_samples));
  std::printf(" -> %s\n", options.out.c_str());
  if (foveated || model)
    std::printf("%s\n", display_line(settings.foveation.display, has_display(options.foveation.display)
                                                                     ? ""
                                                                     : "FIPR's default, a 24-inch display at 600 mm")
                            .c_str());
}
}  // namespace

void add_render_command(CLI::App& app) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* command = app.add_subcommand("render", "Render one frame of a scene to an image");
  command
      ->add_option(
          "--scene", options->scene,
          "Built-in scene name or path to a .glsl scene file (volume, fvolume: a volume scene, built-in or .toml)")
      ->required();
  command
      ->add_option(
          "--method", options->method,
          "gt (ground truth), ipr (inverted pyramid), fipr (foveated inverted pyramid), or a sampling model of Ye et "
          "al. 2022: "
          "rmfr (rectangular mapping), hyperbolic (three layers), linear (linear fall-off), kfr (kernel log-polar), "
          "or Bruder et al. 2019's volume raycaster: volume (every pixel), fvolume (Voronoi foveated); these take a "
          "volume scene")
      ->check(CLI::IsMember({"gt", "ipr", "fipr", "rmfr", "hyperbolic", "linear", "kfr", "volume", "fvolume"}));
  command->add_option("--width", options->settings.width, "Frame width in pixels")->required();
  command->add_option("--height", options->settings.height, "Frame height in pixels")->required();
  command->add_option("--spp", options->settings.samples_per_pixel, "Samples per pixel: 1, 4 or 16");
  add_output_option(*command, "--out", options->out, "Image to write (.png: sRGB, .exr: linear)",
                    {{OutputKind::image_file}, kReplacesAFile})
      ->required();
  add_output_option(*command, "--steps-out", options->steps_out, "Step-count heat map to write (blue 1 step, red cap)",
                    {{OutputKind::image_file}, kReplacesAFile});
  add_output_option(*command, "--stats-json", options->stats_json, "Statistics of the frame as JSON",
                    {{OutputKind::file}, kReplacesAFile});
  command->add_option("--device", options->device, "Vulkan device: index or part of its name (fovlab devices)");
  command->add_option("--frames", options->frames, "Frames to render in sequence (the last is written)");
  command->add_option("--frame-rate", options->frame_rate_hz, "Frames per second of scene time in a sequence");
  add_output_option(*command, "--mask-out", options->mask_out,
                    "Foveation mask image to write (FIPR: white where traced in full; sampling models: samples per "
                    "pixel, white 1 or more)",
                    {{OutputKind::image_file}, kReplacesAFile});
  add_output_option(
      *command, "--density-out", options->density_out,
      "Sampling models: image of the sampling density (samples per pixel; white 1 or more, log scale below)",
      {{OutputKind::image_file}, kReplacesAFile});
  add_trace_options(*command, options->settings);
  add_foveation_flags(*command, options->foveation, FoveationPoint::single);
  add_sampling_flags(*command, options->sampling);
  command->add_option("--step-voxels", options->volume.step_voxels,
                      "volume, fvolume: the base step along a ray, in voxels (0.5)");
  command->add_option("--sigma-deg", options->volume.sigma_deg,
                      "fvolume: radius s of the sampling density's Gaussian, in degrees of visual angle (2.5)");
  command->add_flag("--no-opacity-correction{false}", options->volume.correct_opacity,
                    "fvolume: do not correct the opacity for the longer peripheral step (the authors' code)");
  command->add_flag("--no-smoothing{false}", options->volume.smoothing, "fvolume: no temporal smoothing over --frames");
  command->callback([options, command] {
    options->fipr_flags_given = given_fipr_only_flags(*command);
    options->sampling_flags_given = given_sampling_only_flags(*command);
    options->pyramid_flags_given = given_pyramid_flags(*command);
    if (options->method == "volume" || options->method == "fvolume") return run_volume_render(*options, *command);
    run_render(*options);
  });
}

}  // namespace fovlab::app

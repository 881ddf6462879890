// fovlab bench-fpt: the emulated foveated path tracer's figures in one run (docs/benchmarks.md,
// docs/foveated-path-tracing.md). A full-size frame (ground-truth sphere tracing of a scene) becomes
// the zone buffers of Polychronakis et al. 2021 (nearest decimation by 2 and 4); their Lanczos-3 upsampling back to
// full size is timed on the GPU against OpenImageIO's resize of the same images, and checked against
// the double-precision reference; the gaze-contingent blend is timed against plain copies of one
// full-size buffer; the path tracer's samples per second are measured on the studies' sequence.
// Prints a Markdown table; --json writes every figure.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>

#include <OpenImageIO/oiioversion.h>
#include <nlohmann/json.hpp>

#include "app/cli_support.h"
#include "app/commands.h"
#include "app/display_flags.h"
#include "app/foveation_flags.h"  // display_flags_text
#include "app/output_options.h"
#include "bench/fpt_timing.h"
#include "core/atomic_file.h"
#include "core/input_error.h"
#include "core/number_text.h"
#include "renderer/path_tracing/path_tracer.h"
#include "renderer/prerender/path_scene_source.h"
#include "renderer/scene/scene_source.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/upsampling/upsampler.h"
#include "renderer/vk/context.h"
#include "renderer/zone_blend/zone_blender.h"

namespace fovlab::app {

using namespace fovlab::bench;  // the benchmark library this command prints

namespace {

struct BenchFptOptions {
  std::string scene = "temple";
  int width = 1920;
  int height = 1080;
  int repeats = 9;
  DisplayFlags display;  // default: Polychronakis et al. 2021's 27-inch monitor at 500 mm, gaze at the centre
  double foveal_deg = 10.0;
  std::string path_scene = "courtyard";
  int path_width = 256;  // the Polychronakis et al. 2021 studies' stimulus (experiments/fpt_pair.toml)
  int path_height = 144;
  int path_samples = 128;
  int path_bounces = 32;
  std::filesystem::path json;
  std::string device;
};

// The command that gives the same run, every flag written out (the display's filled in).
std::string command_line(const BenchFptOptions& o) {
  return "fovlab bench-fpt --scene " + o.scene + " --width " + std::to_string(o.width) + " --height " +
         std::to_string(o.height) + " --repeats " + std::to_string(o.repeats) + " " + display_flags_text(o.display) +
         " --foveal-deg " + format_number(o.foveal_deg, 6) + " --path-scene " + o.path_scene + " --path-width " +
         std::to_string(o.path_width) + " --path-height " + std::to_string(o.path_height) + " --path-samples " +
         std::to_string(o.path_samples) + " --path-bounces " + std::to_string(o.path_bounces);
}

void check_options(const BenchFptOptions& o) {
  if (o.width < 4 || o.height < 4 || o.width % 4 != 0 || o.height % 4 != 0 || o.width > 16384 || o.height > 16384)
    throw InputError("--width/--height " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                     ": expected multiples of 4 from 4 to 16384 (the outer zone is 1/4 per axis)");
  if (o.repeats < 1 || o.repeats > 1000)
    throw InputError("--repeats " + std::to_string(o.repeats) + ": expected 1 to 1000");
  if (!is_path_scene_name(o.path_scene))
    throw InputError("--path-scene " + o.path_scene + ": expected " + known_path_scenes() + " or an .obj file");
}

void run_bench_fpt(BenchFptOptions options) {
  check_options(options);
  default_to_fpt_study_display(options.display);
  const DisplayGeometry display = parse_display(options.display, options.width, options.height);
  const auto [gaze_x, gaze_y] = parse_gaze(options.display.gaze, options.width, options.height);
  const ZoneBounds bounds{options.foveal_deg, default_middle_deg(options.foveal_deg), 1.0};
  check_zone_bounds(bounds);
  PathTraceSettings path_settings;
  path_settings.width_px = options.path_width;
  path_settings.height_px = options.path_height;
  path_settings.samples_per_pixel = options.path_samples;
  path_settings.max_bounces = options.path_bounces;
  validate(path_settings);
  const std::filesystem::path json_folder = options.json.parent_path();
  if (!options.json.empty() && !json_folder.empty() && !std::filesystem::is_directory(json_folder))
    throw InputError("--json " + options.json.string() + ": expected a file in an existing folder");
  const LoadedPathScene path_scene = load_path_scene(options.path_scene);
  const SceneSource scene = load_scene(options.scene);

  vk::Context context(context_options(options.device));
  check_zone_frame_size(context, options.width, options.height);
  // The frame: linear light, as a pre-rendered path-traced frame would be.
  SphereTraceSettings frame_settings;
  frame_settings.width = options.width;
  frame_settings.height = options.height;
  frame_settings.outputs = TraceOutputs::colour;
  const Image frame = SphereTracer(context, scene).render(frame_settings).colour_linear;

  nlohmann::json report = {{"device", context.description.name},
                           {"frame", {{"scene", options.scene}, {"width", options.width}, {"height", options.height}}}};
  std::string table =
      "| what | fovlab (median ms) | baseline (median ms) | fovlab / baseline | largest difference |\n"
      "|---|---:|---:|---:|---|\n";
  char row[512];

  Upsampler upsampler(context);
  for (int factor : {2, 4}) {
    const Image zone = decimate_nearest(frame, factor);
    const UpsampleTiming timing =
        time_upsampling(upsampler, zone, factor, UpsampleFilter::lanczos3, options.repeats, true);
    report["upsample_factor_" + std::to_string(factor)] = timing.json();
    std::snprintf(row, sizeof row,
                  "| Lanczos-3, %dx%d to %dx%d (GPU; OpenImageIO %s resize, CPU, wall) | %.2f | %.2f | %.2f | GPU - "
                  "reference %.2g, OpenImageIO - reference %.2g (values %.2g to %.2g) |\n",
                  zone.width, zone.height, zone.width * factor, zone.height * factor, OIIO_VERSION_STRING,
                  timing.gpu_median_ms, timing.openimageio_median_ms,
                  timing.gpu_median_ms / timing.openimageio_median_ms, timing.gpu_vs_reference,
                  timing.openimageio_vs_reference, timing.input_low, timing.input_high);
    table += row;
  }

  ZoneBlender blender(context);
  const double zone_buffers_ms = time_zone_buffers(blender, frame, options.repeats);
  report["zone_buffers_gpu_ms"] = zone_buffers_ms;
  std::snprintf(row, sizeof row,
                "| an animation frame's zone buffers: both upsamplings and the sRGB8 encoding of three zones (GPU) "
                "| %.2f | | | |\n",
                zone_buffers_ms);
  table += row;
  const BlendTiming blend = time_blend(blender, display, gaze_x, gaze_y, bounds, options.repeats);
  report["blend"] = blend.json();
  report["blend"]["bounds_deg"] = {
      {"foveal", bounds.foveal_deg}, {"middle", bounds.middle_deg}, {"band", bounds.band_deg}};
  report["blend"]["gaze_px"] = {gaze_x, gaze_y};
  for (const auto& [name, ms] : {std::pair{"to the sRGB8 frame (sessions)", blend.display_blend_ms},
                                 std::pair{"to float RGBA (previews)", blend.linear_blend_ms}}) {
    std::snprintf(row, sizeof row, "| blend %s, against a copy shader | %.2f | %.2f | %.2f | |\n", name, ms,
                  blend.copy_shader_ms, ms / blend.copy_shader_ms);
    table += row;
    std::snprintf(row, sizeof row, "| blend %s, against vkCmdCopyBuffer | %.2f | %.2f | %.2f | |\n", name, ms,
                  blend.copy_buffer_ms, ms / blend.copy_buffer_ms);
    table += row;
  }
  std::snprintf(row, sizeof row, "| a session's refresh: sRGB8 blend read back (wall) | %.2f | | | |\n",
                blend.refresh_wall_ms);
  table += row;
  std::snprintf(row, sizeof row,
                "| band pixels, blended by the display blend's second pass | %u of %u (%.1f %%) | | | |\n",
                blend.band_pixels, blend.frame_pixels, 100.0 * blend.band_pixels / std::max(1u, blend.frame_pixels));
  table += row;

  PathTracer tracer(context, path_scene.scene);
  const auto started = std::chrono::steady_clock::now();
  const PathTraceResult traced = tracer.render(path_settings);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const double gpu_rate = samples_per_second(traced.samples, traced.gpu_ms);
  const double wall_rate = samples_per_second(traced.samples, 1000.0 * wall_s);
  report["path_tracer"] = {{"scene", options.path_scene},
                           {"width", options.path_width},
                           {"height", options.path_height},
                           {"samples_per_pixel", options.path_samples},
                           {"max_bounces", options.path_bounces},
                           {"samples", traced.samples},
                           {"gpu_ms", traced.gpu_ms},
                           {"wall_s", wall_s},
                           {"samples_per_s_gpu", gpu_rate},
                           {"samples_per_s_wall", wall_rate}};
  fail_on_validation_messages(context);

  report["command"] = command_line(options);
  std::printf(
      "# fovlab bench-fpt\n\nCommand: `%s`\n\nDevice: %s; median of %d runs; frame: %s GT at %dx%d; blend: gaze "
      "%.0f,%.0f px, foveal %g, middle %g, band %g degrees.\n\n%s\n",
      report["command"].get<std::string>().c_str(), context.description.name.c_str(), options.repeats,
      options.scene.c_str(), options.width, options.height, gaze_x, gaze_y, bounds.foveal_deg, bounds.middle_deg,
      bounds.band_deg, table.c_str());
  std::printf(
      "Path tracer, %s %dx%d, %d samples per pixel, %d bounces: %.3g samples/s on the GPU clock, %.3g on the "
      "wall clock (%.1f s)\n",
      options.path_scene.c_str(), options.path_width, options.path_height, options.path_samples, options.path_bounces,
      gpu_rate, wall_rate, wall_s);
  if (!options.json.empty()) write_text_atomically(options.json, report.dump(2) + "\n");
}

}  // namespace

void add_bench_fpt_command(CLI::App& app) {
  auto options = std::make_shared<BenchFptOptions>();
  CLI::App* command = app.add_subcommand(
      "bench-fpt",
      "Time the emulated foveated path tracer: upsampling against OpenImageIO, blend against a copy, path tracer");
  command->add_option("--scene", options->scene, "Sphere-traced scene whose GT frame is the blended frame (temple)");
  command->add_option("--width", options->width, "Frame width, a multiple of 4 (1920)");
  command->add_option("--height", options->height, "Frame height, a multiple of 4 (1080)");
  command->add_option("--repeats", options->repeats, "Timed runs of each (median reported; 9)");
  add_display_flags(*command, options->display, false);  // default: 27" at 500 mm (Polychronakis et al. 2021)
  command->add_option("--foveal-deg", options->foveal_deg, "Foveal zone of the blend, full aperture (10)");
  command->add_option("--path-scene", options->path_scene, "Path-traced scene: courtyard or an .obj file");
  command->add_option("--path-width", options->path_width, "Path-traced frame width (256)");
  command->add_option("--path-height", options->path_height, "Path-traced frame height (144)");
  command->add_option("--path-samples", options->path_samples, "Samples per pixel (128)");
  command->add_option("--path-bounces", options->path_bounces, "Bounces (32)");
  add_output_option(*command, "--json", options->json, "Write every figure as JSON",
                    {{OutputKind::file}, kReplacesAFile});
  command->add_option("--device", options->device, "Vulkan device: index or part of its name (fovlab devices)");
  command->callback([options] { run_bench_fpt(*options); });
}

}  // namespace fovlab::app

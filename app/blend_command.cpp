// fovlab blend --frame IMG --gaze X,Y --foveal-deg E [--middle-deg M] [--band-deg B] --out IMG
//              [--zones-out IMG]: an offline preview of what a participant of the emulated foveated
// path tracer sees for one frame and one gaze sample (renderer/zone_blend;
// docs/foveated-path-tracing.md). The frame's three zone buffers are made and blended on the GPU.
// --repeats N also times the blend against plain copies of one full-size buffer (a copy shader and
// vkCmdCopyBuffer).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/cli_support.h"
#include "app/commands.h"
#include "app/display_flags.h"
#include "bench/fpt_timing.h"
#include "app/output_options.h"
#include "app/render_outputs.h"
#include "core/colour.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "renderer/vk/context.h"
#include "renderer/zone_blend/zone_blender.h"

namespace fovlab::app {

using namespace fovlab::bench;  // the benchmark library this command prints

namespace {

struct BlendOptions {
  std::filesystem::path frame;
  std::filesystem::path periphery_frame;
  DisplayFlags display;
  double foveal_deg = 0.0;
  std::optional<double> middle_deg;
  double band_deg = 1.0;
  std::filesystem::path out;
  std::filesystem::path zones_out;
  std::string device;
  int repeats = 0;
};

// The frame under the zone colours (red foveal, green middle, blue outer), half and half.
Image zones_over_frame(const Image& zones, const Image& frame_display) {
  Image picture(zones.width, zones.height, 3);
  for (int y = 0; y < zones.height; ++y)
    for (int x = 0; x < zones.width; ++x) {
      const int colour_channels = std::min(frame_display.channels, 3);
      float grey = 0.0f;
      for (int c = 0; c < colour_channels; ++c) grey += frame_display.at(x, y, c) / float(colour_channels);
      for (int c = 0; c < 3; ++c) picture.at(x, y, c) = 0.5f * grey + 0.5f * zones.at(x, y, c);
    }
  return picture;
}

void run_blend(BlendOptions options) {
  const std::string assumed_display = default_to_fpt_study_display(options.display);
  if (options.repeats < 0 || options.repeats > 1000)
    throw InputError("--repeats " + std::to_string(options.repeats) + ": expected 0 to 1000");
  const Image frame = read_image(options.frame);
  const DisplayGeometry display = parse_display(options.display, frame.width, frame.height);
  const auto [gaze_x, gaze_y] = parse_gaze(options.display.gaze, frame.width, frame.height);
  if (gaze_x < 0 || gaze_y < 0 || gaze_x > frame.width || gaze_y > frame.height)
    fail_flag("--gaze", "a point on the " + std::to_string(frame.width) + "x" + std::to_string(frame.height) + " frame",
              options.display.gaze);
  const ZoneBounds bounds{options.foveal_deg, options.middle_deg.value_or(default_middle_deg(options.foveal_deg)),
                          options.band_deg};
  check_zone_bounds(bounds);
  std::optional<Image> periphery;
  if (!options.periphery_frame.empty()) periphery = read_image(options.periphery_frame);

  vk::Context context(context_options(options.device));
  ZoneBlender blender(context);
  const double zone_buffers_ms = blender.set_frame(frame, periphery ? &*periphery : nullptr);
  const ZoneBlendResult result = blender.blend(display, gaze_x, gaze_y, bounds);
  BlendTiming timing;
  if (options.repeats > 0) timing = time_blend(blender, display, gaze_x, gaze_y, bounds, options.repeats);
  fail_on_validation_messages(context);

  // EXR frames are linear light: written linear to EXR, sRGB-encoded to 8-bit files. Other frames
  // are blended as stored and written as they are.
  const bool linear = lower_extension(options.frame) == ".exr";
  if (linear) write_colour(options.out, result.image);
  else write_image(options.out, result.image);
  if (!options.zones_out.empty())
    write_image(options.zones_out,
                zones_over_frame(zone_map(display, gaze_x, gaze_y, bounds), linear ? encode_srgb(frame) : frame));
  std::printf(
      "%s %dx%d, gaze %.1f,%.1f px, foveal %g deg, middle %g deg, band %g deg: zone buffers %.2f ms, blend %.2f ms "
      "GPU -> %s\n",
      options.frame.c_str(), frame.width, frame.height, gaze_x, gaze_y, bounds.foveal_deg, bounds.middle_deg,
      bounds.band_deg, zone_buffers_ms, result.gpu_ms, options.out.c_str());
  std::printf("%s\n", display_line(display, assumed_display).c_str());
  if (options.repeats > 0) print_blend_timing(timing);
}

}  // namespace

void add_blend_command(CLI::App& app) {
  auto options = std::make_shared<BlendOptions>();
  CLI::App* command =
      app.add_subcommand("blend", "Preview the emulated foveated path tracer's three-zone blend for one gaze sample");
  command->add_option("--frame", options->frame, "Full-resolution frame (EXR: linear light)")->required();
  command->add_option("--periphery-frame", options->periphery_frame,
                      "Source of the middle and outer zones instead of the frame (e.g. fewer bounces)");
  add_display_flags(*command, options->display, false);  // default: 27" at 500 mm (Polychronakis et al. 2021)
  command->get_option("--gaze")->required()->description("Gaze point X,Y in pixels, or each in percent of the frame");
  command->add_option("--foveal-deg", options->foveal_deg, "Foveal zone, full aperture in degrees")->required();
  command->add_option("--middle-deg", options->middle_deg, "Middle zone, full aperture (default foveal + 52.5)");
  command->add_option("--band-deg", options->band_deg, "Width of the linear band at each boundary (default 1)");
  add_output_option(*command, "--out", options->out, "Blended image (.png: sRGB, .exr: linear)",
                    {{OutputKind::image_file}, kReplacesAFile})
      ->required();
  add_output_option(*command, "--zones-out", options->zones_out, "Picture of the zones over the frame",
                    {{OutputKind::image_file}, kReplacesAFile});
  command->add_option("--device", options->device, "Vulkan device: index or part of its name (fovlab devices)");
  command->add_option("--repeats", options->repeats, "Also time the blend against a plain copy, N times");
  command->callback([options] { run_blend(*options); });
}

}  // namespace fovlab::app

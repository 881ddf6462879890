// fovlab resample --frame IMG --method rmfr|hyperbolic|linear|kfr [model flags] --gaze X,Y --out IMG
//                 [--mask-out IMG] [--density-out IMG] [--repeats N]: an offline preview of Ye et al. 2022's
// sampling models on a pre-rendered frame, what a participant of pt-rmfr, pt-hyperbolic, pt-linear
// or pt-kfr sees for one gaze sample (renderer/foveated_sampling/frame_sampler.h; an EXR frame, in
// linear light as the pre-render cache holds them). Prints what the
// map samples, the GPU time of its passes (median of --repeats) and the error against the frame
// itself (SSIM, PSNR, FLIP, FPSNR at the gaze).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "app/cli_support.h"
#include "app/commands.h"
#include "app/display_flags.h"
#include "app/output_options.h"
#include "app/render_outputs.h"
#include "app/sampling_flags.h"
#include "bench/frame_errors.h"
#include "core/colour.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "renderer/foveated_sampling/frame_sampler.h"
#include "renderer/vk/context.h"

namespace fovlab::app {

namespace {

struct ResampleOptions {
  std::filesystem::path frame;
  std::string method;
  SamplingSettings sampling;
  std::vector<std::string> sampling_flags_given;
  DisplayFlags display;
  std::filesystem::path out;
  std::filesystem::path mask_out;
  std::filesystem::path density_out;
  std::string device;
  int repeats = 1;
};

std::string optional_db(const std::optional<double>& db) {
  if (!db) return "identical";
  char text[32];
  std::snprintf(text, sizeof text, "%.2f dB", *db);
  return text;
}

void run_resample(ResampleOptions options) {
  const std::optional<SamplingModel> model = parse_sampling_model(options.method);
  if (!model) throw std::logic_error("resample: --method is checked by CLI11");
  refuse_flags_unused_by(options.sampling_flags_given, {*model});
  const std::string assumed_display = default_to_fpt_study_display(options.display);
  if (options.repeats < 1 || options.repeats > 1000)
    throw InputError("--repeats " + std::to_string(options.repeats) + ": expected 1 to 1000");
  Image frame = read_image(options.frame);
  if (frame.channels != 3) {  // colour only: grey repeated in each channel, alpha dropped (the metrics compare RGB)
    Image rgb(frame.width, frame.height, 3);
    for (int y = 0; y < frame.height; ++y)
      for (int x = 0; x < frame.width; ++x)
        for (int c = 0; c < 3; ++c) rgb.at(x, y, c) = frame.at(x, y, frame.channels < 3 ? 0 : c);
    frame = std::move(rgb);
  }
  FoveationSettings where;
  where.display = parse_display(options.display, frame.width, frame.height);
  std::tie(where.gaze_x_px, where.gaze_y_px) = parse_gaze(options.display.gaze, frame.width, frame.height);
  // As a session: equalise solved with the gaze at the centre, that solution kept for the gaze.
  FoveationSettings centre = where;
  centre.gaze_x_px = centre.gaze_y_px = std::nan("");
  SamplingSettings settings = options.sampling;
  if (settings.equalise != Equalise::off)
    settings = with_solved_equalise(settings, parse_sampling(*model, settings, centre));
  const SamplingMap map = parse_sampling(*model, settings, where);

  vk::Context context(context_options(options.device));
  FrameSampler sampler(context);
  sampler.set_frame(frame);
  FrameSamplingResult result;
  std::vector<double> gpu_ms;
  for (int repeat = 0; repeat < options.repeats; ++repeat) {
    result = sampler.resample(map, options.sampling.filter, !options.mask_out.empty());
    gpu_ms.push_back(result.gpu_ms);
  }
  fail_on_validation_messages(context);
  std::sort(gpu_ms.begin(), gpu_ms.end());

  // EXR frames are linear light: written linear to EXR, sRGB-encoded to 8-bit files, and compared
  // sRGB-encoded. Other frames (PNG) are averaged as stored, in their encoded values, and written
  // and compared as they are: a preview of those is approximate (a session's frames are linear).
  // Equalise: as a session solves it, with the gaze at the centre.
  const bool linear = lower_extension(options.frame) == ".exr";
  if (linear) write_colour(options.out, result.colour_linear);
  else write_image(options.out, result.colour_linear);
  if (!options.mask_out.empty()) write_image(options.mask_out, samples_per_pixel_image(result.samples_per_pixel));
  if (!options.density_out.empty()) write_image(options.density_out, density_image(map));
  const bench::FrameErrors errors =
      linear ? bench::frame_errors(encode_srgb(frame), encode_srgb(result.colour_linear), where.display,
                                   where.gaze_x_px, where.gaze_y_px)
             : bench::frame_errors(frame, result.colour_linear, where.display, where.gaze_x_px, where.gaze_y_px);
  std::printf("%s %dx%d, gaze %.1f,%.1f px, %s; %llu samples read, %.2f ms GPU (median of %d)\n", options.frame.c_str(),
              frame.width, frame.height, where.gaze_x_px, where.gaze_y_px, sampling_summary(map).c_str(),
              static_cast<unsigned long long>(result.shaded_samples), gpu_ms[gpu_ms.size() / 2], options.repeats);
  std::printf("against the frame: SSIM %.4f, PSNR %s, FLIP %.4f, FPSNR %s -> %s\n", errors.ssim,
              optional_db(errors.psnr_db).c_str(), errors.flip, optional_db(errors.fpsnr_db).c_str(),
              options.out.c_str());
  std::printf("%s\n", display_line(where.display, assumed_display).c_str());
}

}  // namespace

void add_resample_command(CLI::App& app) {
  auto options = std::make_shared<ResampleOptions>();
  CLI::App* command = app.add_subcommand(
      "resample",
      "Preview a sampling model of Ye et al. 2022 on a pre-rendered frame for one gaze sample (pt-rmfr, ...)");
  command->add_option("--frame", options->frame, "Full-resolution frame (EXR: linear light)")->required();
  command
      ->add_option(
          "--method", options->method,
          "rmfr (rectangular mapping), hyperbolic (three layers), linear (linear fall-off), kfr (kernel log-polar)")
      ->required()
      ->check(CLI::IsMember({"rmfr", "hyperbolic", "linear", "kfr"}));
  add_display_flags(*command, options->display, false);  // default: 27" at 500 mm (Polychronakis et al. 2021's frames)
  command->get_option("--gaze")->description(
      "Gaze point X,Y in pixels, or each in percent of the frame (default: the centre)");
  add_sampling_flags(*command, options->sampling);
  add_output_option(*command, "--out", options->out, "Resampled image (.png: sRGB, .exr: linear)",
                    {{OutputKind::image_file}, kReplacesAFile})
      ->required();
  add_output_option(*command, "--mask-out", options->mask_out, "Samples per pixel (white 1 or more)",
                    {{OutputKind::image_file}, kReplacesAFile});
  add_output_option(*command, "--density-out", options->density_out,
                    "The model's sampling density (samples per pixel; white 1 or more, log scale below)",
                    {{OutputKind::image_file}, kReplacesAFile});
  command->add_option("--repeats", options->repeats, "Run the passes N times; the median GPU time is printed");
  command->add_option("--device", options->device, "Vulkan device: index or part of its name (fovlab devices)");
  command->callback([options, command] {
    options->sampling_flags_given = given_sampling_only_flags(*command);
    run_resample(*options);
  });
}

}  // namespace fovlab::app

// fovlab upsample IN --factor 2|4 [--filter lanczos3|bilinear|nearest] --out OUT: one zone buffer
// brought back to full size on the GPU (renderer/upsampling; docs/foveated-path-tracing.md). Float
// files (EXR) keep full precision in and out; 8-bit files are filtered as they are stored.
// --repeats N times the GPU passes (median); --against-oiio also times OpenImageIO's own lanczos3
// resize of the same image on the CPU (all cores) and prints how far the three results differ.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <OpenImageIO/oiioversion.h>

#include "app/cli_support.h"
#include "app/commands.h"
#include "app/output_options.h"
#include "bench/fpt_timing.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "renderer/upsampling/upsampler.h"
#include "renderer/vk/context.h"

namespace fovlab::app {

using namespace fovlab::bench;  // the benchmark library this command prints

namespace {

struct UpsampleOptions {
  std::filesystem::path in;
  int factor = 2;
  std::string filter = "lanczos3";
  std::filesystem::path out;
  std::string device;
  int repeats = 1;
  bool against_oiio = false;
};

void run_upsample(const UpsampleOptions& options) {
  if (options.factor != 2 && options.factor != 4)
    throw InputError("--factor " + std::to_string(options.factor) +
                     ": expected 2 or 4 (per axis: 1/4 or 1/16 of the pixels)");
  const UpsampleFilter filter = parse_upsample_filter(options.filter).value_or(UpsampleFilter::lanczos3);
  if (options.repeats < 1 || options.repeats > 1000)
    throw InputError("--repeats " + std::to_string(options.repeats) + ": expected 1 to 1000");
  if (options.against_oiio && filter != UpsampleFilter::lanczos3)
    throw InputError("--against-oiio: compares Lanczos-3 only; leave --filter at lanczos3");
  const Image image = read_image(options.in);
  if (image.channels < 1 || image.channels > 4)
    throw InputError(options.in.string() + ": " + std::to_string(image.channels) + " channels; expected 1 to 4");
  vk::Context context(context_options(options.device));
  Upsampler upsampler(context);
  const UpsampleTiming timing =
      time_upsampling(upsampler, image, options.factor, filter, options.repeats, options.against_oiio);
  fail_on_validation_messages(context);
  write_image(options.out, timing.upsampled);
  std::printf("%s %dx%d -> %dx%d (%s, factor %d): %.2f ms GPU (median of %d) -> %s\n", options.in.c_str(), image.width,
              image.height, timing.upsampled.width, timing.upsampled.height, upsample_filter_name(filter),
              options.factor, timing.gpu_median_ms, options.repeats, options.out.c_str());
  if (!timing.against_openimageio) return;
  std::printf("OpenImageIO %s resize (lanczos3, CPU): %.2f ms wall (median of %d); GPU / OpenImageIO time %.2f\n",
              OIIO_VERSION_STRING, timing.openimageio_median_ms, options.repeats,
              timing.gpu_median_ms / timing.openimageio_median_ms);
  std::printf(
      "largest difference (input values %.3g to %.3g): GPU - reference %.3g, OpenImageIO - reference %.3g, "
      "GPU - OpenImageIO %.3g\n",
      timing.input_low, timing.input_high, timing.gpu_vs_reference, timing.openimageio_vs_reference,
      timing.gpu_vs_openimageio);
}

}  // namespace

void add_upsample_command(CLI::App& app) {
  auto options = std::make_shared<UpsampleOptions>();
  CLI::App* command = app.add_subcommand("upsample", "Upsample a zone buffer by 2 or 4 per axis on the GPU");
  command->add_option("in", options->in, "Image to upsample (EXR keeps full precision)")->required();
  command->add_option("--factor", options->factor, "Factor per axis: 2 or 4")->required();
  command->add_option("--filter", options->filter, "lanczos3 (default), bilinear or nearest")
      ->check(CLI::IsMember({"lanczos3", "bilinear", "nearest"}));
  add_output_option(*command, "--out", options->out, "Image to write", {{OutputKind::image_file}, kReplacesAFile})
      ->required();
  command->add_option("--device", options->device, "Vulkan device: index or part of its name (fovlab devices)");
  command->add_option("--repeats", options->repeats, "Timed runs (the median is printed)");
  command->add_flag("--against-oiio", options->against_oiio,
                    "Also time OpenImageIO's lanczos3 resize of the same image and print the differences");
  command->callback([options] { run_upsample(*options); });
}

}  // namespace fovlab::app

// fovlab upsample IN --factor 2|4 [--filter lanczos3|bilinear|nearest] --out OUT: one zone buffer
// brought back to full size on the GPU (renderer/upsampling; docs/foveated-path-tracing.md). Float
// files (EXR) keep full precision in and out; 8-bit files are filtered as they are stored.
#include <cstdio>
#include <memory>
#include <string>

#include "app/cli_support.h"
#include "app/commands.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "renderer/upsampling/upsampler.h"
#include "renderer/vk/context.h"

namespace fovlab::app {

namespace {

struct UpsampleOptions {
  std::filesystem::path in;
  int factor = 2;
  std::string filter = "lanczos3";
  std::filesystem::path out;
  std::string device;
};

void run_upsample(const UpsampleOptions& options) {
  if (options.factor != 2 && options.factor != 4)
    throw InputError("--factor " + std::to_string(options.factor) + ": expected 2 or 4 (per axis: 1/4 or 1/16 of the pixels)");
  const UpsampleFilter filter = parse_upsample_filter(options.filter).value_or(UpsampleFilter::lanczos3);
  check_image_output_path(options.out, "--out");
  const Image image = read_image(options.in);
  if (image.channels < 1 || image.channels > 4)
    throw InputError(options.in.string() + ": " + std::to_string(image.channels) + " channels; expected 1 to 4");
  vk::Context context(context_options(options.device));
  Upsampler upsampler(context);
  const UpsampleResult result = upsampler.upsample(image, options.factor, filter);
  fail_on_validation_messages(context);
  write_image(options.out, result.image);
  std::printf("%s %dx%d -> %dx%d (%s, factor %d): %.2f ms GPU -> %s\n", options.in.c_str(), image.width, image.height,
              result.image.width, result.image.height, upsample_filter_name(filter), options.factor, result.gpu_ms,
              options.out.c_str());
}

}  // namespace

void add_upsample_command(CLI::App& app) {
  auto options = std::make_shared<UpsampleOptions>();
  CLI::App* command = app.add_subcommand("upsample", "Upsample a zone buffer by 2 or 4 per axis on the GPU");
  command->add_option("in", options->in, "Image to upsample (EXR keeps full precision)")->required();
  command->add_option("--factor", options->factor, "Factor per axis: 2 or 4")->required();
  command->add_option("--filter", options->filter, "lanczos3 (default), bilinear or nearest")
      ->check(CLI::IsMember({"lanczos3", "bilinear", "nearest"}));
  command->add_option("--out", options->out, "Image to write")->required();
  command->add_option("--device", options->device, "Vulkan device: index or part of its name (fovlab devices)");
  command->callback([options] { run_upsample(*options); });
}

}  // namespace fovlab::app

// fovlab upsample IN --factor 2|4 [--filter lanczos3|bilinear|nearest] --out OUT: one zone buffer
// brought back to full size on the GPU (renderer/upsampling; docs/foveated-path-tracing.md). Float
// files (EXR) keep full precision in and out; 8-bit files are filtered as they are stored.
// --repeats N times the GPU passes (median); --against-oiio also times OpenImageIO's own lanczos3
// resize of the same image on the CPU (all cores) and prints how far the three results differ.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <OpenImageIO/imagebufalgo.h>

#include "app/bench_runs.h"  // median
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
  int repeats = 1;
  bool against_oiio = false;
};

// Over the pixels at least `margin` pixels from every border.
double largest_difference(const Image& a, const Image& b, int margin = 0) {
  double largest = 0.0;
  for (int y = margin; y < a.height - margin; ++y)
    for (int x = margin; x < a.width - margin; ++x)
      for (int c = 0; c < a.channels; ++c) largest = std::max(largest, double(std::fabs(a.at(x, y, c) - b.at(x, y, c))));
  return largest;
}

// OpenImageIO's resize of the same image to the same size with its "lanczos3" filter (width 6),
// timed on the wall clock (it runs on the CPU, on every core).
Image oiio_resize(const Image& image, int factor, double& wall_ms) {
  const OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf source(spec, const_cast<float*>(image.pixels.data()));
  const OIIO::ROI roi(0, image.width * factor, 0, image.height * factor, 0, 1, 0, image.channels);
  const auto started = std::chrono::steady_clock::now();
  OIIO::ImageBuf resized = OIIO::ImageBufAlgo::resize(source, "lanczos3", 6.0f, roi);
  wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  if (resized.has_error()) throw InputError("OpenImageIO resize: " + resized.geterror());
  Image out(image.width * factor, image.height * factor, image.channels);
  resized.get_pixels(roi, OIIO::TypeDesc::FLOAT, out.pixels.data());
  return out;
}

void run_upsample(const UpsampleOptions& options) {
  if (options.factor != 2 && options.factor != 4)
    throw InputError("--factor " + std::to_string(options.factor) + ": expected 2 or 4 (per axis: 1/4 or 1/16 of the pixels)");
  const UpsampleFilter filter = parse_upsample_filter(options.filter).value_or(UpsampleFilter::lanczos3);
  if (options.repeats < 1 || options.repeats > 1000)
    throw InputError("--repeats " + std::to_string(options.repeats) + ": expected 1 to 1000");
  if (options.against_oiio && filter != UpsampleFilter::lanczos3)
    throw InputError("--against-oiio: compares Lanczos-3 only; leave --filter at lanczos3");
  check_image_output_path(options.out, "--out");
  const Image image = read_image(options.in);
  if (image.channels < 1 || image.channels > 4)
    throw InputError(options.in.string() + ": " + std::to_string(image.channels) + " channels; expected 1 to 4");
  vk::Context context(context_options(options.device));
  Upsampler upsampler(context);
  UpsampleResult result;
  std::vector<double> gpu_ms;
  for (int run = 0; run < options.repeats; ++run) {
    result = upsampler.upsample(image, options.factor, filter);
    gpu_ms.push_back(result.gpu_ms);
  }
  fail_on_validation_messages(context);
  write_image(options.out, result.image);
  std::printf("%s %dx%d -> %dx%d (%s, factor %d): %.2f ms GPU (median of %d) -> %s\n", options.in.c_str(), image.width,
              image.height, result.image.width, result.image.height, upsample_filter_name(filter), options.factor,
              median(gpu_ms), options.repeats, options.out.c_str());
  if (!options.against_oiio) return;
  std::vector<double> oiio_ms;
  Image oiio;
  for (int run = 0; run < options.repeats; ++run) {
    double wall_ms = 0.0;
    oiio = oiio_resize(image, options.factor, wall_ms);
    oiio_ms.push_back(wall_ms);
  }
  const Image reference = upsample_reference(image, options.factor, filter);
  std::printf("OpenImageIO %s resize (lanczos3, CPU): %.2f ms wall (median of %d); GPU / OpenImageIO time %.2f\n",
              OIIO_VERSION_STRING, median(oiio_ms), options.repeats, median(gpu_ms) / median(oiio_ms));
  const auto [low, high] = std::minmax_element(image.pixels.begin(), image.pixels.end());
  std::printf("largest difference (input values %.3g to %.3g): GPU - reference %.3g, OpenImageIO - reference %.3g, "
              "GPU - OpenImageIO %.3g\n",
              double(*low), double(*high), largest_difference(result.image, reference), largest_difference(oiio, reference),
              largest_difference(result.image, oiio));
  // Borders are where edge handling differs (fovlab repeats the edge pixel); inside, the filters meet.
  const int margin = 4 * options.factor;
  std::printf("largest difference %d or more pixels from the borders: GPU - OpenImageIO %.3g\n", margin,
              largest_difference(result.image, oiio, margin));
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
  command->add_option("--repeats", options->repeats, "Timed runs (the median is printed)");
  command->add_flag("--against-oiio", options->against_oiio,
                    "Also time OpenImageIO's lanczos3 resize of the same image and print the differences");
  command->callback([options] { run_upsample(*options); });
}

}  // namespace fovlab::app

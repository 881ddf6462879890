// fovlab compare A B: PSNR and SSIM between two images (docs/analysis.md, "Image metrics").
#include <cmath>
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "analysis/image_metrics/image_metrics.h"
#include "app/commands.h"
#include "core/colour.h"
#include "core/image_io.h"
#include "core/input_error.h"

namespace fovlab::app {

namespace {
struct CompareOptions {
  std::filesystem::path a;
  std::filesystem::path b;
  bool json = false;
};

// Floating-point files (EXR) hold linear light: encode them to sRGB so both sides are compared as
// display images, like 8-bit files.
Image read_display_image(const std::filesystem::path& path) {
  Image image = read_image(path);
  if (image.channels != 1 && image.channels != 3 && image.channels != 4) {
    throw InputError(path.string() + ": " + std::to_string(image.channels) +
                     " channels; expected grey (1), RGB (3) or RGBA (4)");
  }
  return lower_extension(path) == ".exr" ? encode_srgb(image) : image;
}

void run_compare(const CompareOptions& options) {
  const Image a = read_display_image(options.a);
  const Image b = read_display_image(options.b);
  if (a.width != b.width || a.height != b.height) {
    throw InputError(options.b.string() + ": " + std::to_string(b.width) + "x" + std::to_string(b.height) +
                     " pixels; expected the size of " + options.a.string() + ", " + std::to_string(a.width) + "x" +
                     std::to_string(a.height));
  }
  if ((a.channels == 1) != (b.channels == 1)) {
    throw InputError(options.b.string() + ": " + std::to_string(b.channels) + " channels; expected a " +
                     (a.channels == 1 ? "grey" : "colour") + " image like " + options.a.string());
  }
  if (a.width < 11 || a.height < 11) {
    throw InputError(options.a.string() + ": " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                     " pixels; SSIM needs at least 11x11");
  }
  const analysis::PsnrResult psnr = analysis::psnr(a, b);
  const analysis::SsimResult ssim = analysis::ssim(a, b);
  if (options.json) {
    nlohmann::json out = {{"a", options.a.string()}, {"b", options.b.string()}, {"mse", psnr.mse},
                          {"identical", psnr.identical}, {"ssim", ssim.mean_ssim}};
    out["psnr_db"] = psnr.identical ? nlohmann::json(nullptr) : nlohmann::json(psnr.psnr_db);
    std::printf("%s\n", out.dump(2).c_str());
  } else {
    if (psnr.identical) {
      std::printf("PSNR inf dB (identical)\n");
    } else {
      std::printf("PSNR %.2f dB\n", psnr.psnr_db);
    }
    std::printf("SSIM %.6f\n", ssim.mean_ssim);
  }
}
}  // namespace

void add_compare_command(CLI::App& app) {
  auto options = std::make_shared<CompareOptions>();
  CLI::App* command = app.add_subcommand("compare", "PSNR and SSIM between two images of the same size");
  command->add_option("a", options->a, "Reference image")->required();
  command->add_option("b", options->b, "Test image")->required();
  command->add_flag("--json", options->json, "Print JSON (psnr_db is null when the images are identical)");
  command->callback([options] { run_compare(*options); });
}

}  // namespace fovlab::app

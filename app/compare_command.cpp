// fovlab compare A B: PSNR, SSIM, FLIP and (with a display) FPSNR between two images
// (docs/analysis.md, "Image metrics").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "metrics/flip.h"
#include "metrics/fpsnr.h"
#include "metrics/image_metrics.h"
#include "app/commands.h"
#include "app/display_flags.h"
#include "core/colour.h"
#include "core/image_io.h"
#include "core/input_error.h"

namespace fovlab::app {

namespace {
struct CompareOptions {
  std::filesystem::path a;
  std::filesystem::path b;
  bool json = false;
  DisplayFlags display;  // optional: FLIP's pixels per degree, and FPSNR
};

// FLIP's own default viewing set-up when no display is given: a 0.7 m wide 4K monitor seen from
// 0.7 m, 67 pixels per degree (Andersson et al. 2020).
constexpr double default_flip_pixels_per_degree = 67.0;

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
  std::optional<DisplayGeometry> display;
  if (has_display(options.display)) display = parse_display(options.display, a.width, a.height);
  const auto [gaze_x, gaze_y] = parse_gaze(options.display.gaze, a.width, a.height);
  if (!options.display.gaze.empty() && !display)
    throw InputError("--gaze: FPSNR needs the display too (--diagonal-in or --size-mm, and --distance-mm)");
  const double pixels_per_degree = display ? display->pixels_per_degree_at_centre() : default_flip_pixels_per_degree;

  const metrics::PsnrResult psnr = metrics::psnr(a, b);
  const metrics::SsimResult ssim = metrics::ssim(a, b);
  // LDR-FLIP is defined for display values in [0, 1]; an HDR file (EXR above 1) has no LDR-FLIP.
  const auto displayable = [](const Image& image) {
    return std::all_of(image.pixels.begin(), image.pixels.end(), [](float v) { return v >= 0.0f && v <= 1.0f; });
  };
  std::optional<metrics::FlipResult> flip;
  if (displayable(a) && displayable(b)) flip = metrics::flip(a, b, pixels_per_degree);
  std::optional<metrics::FpsnrResult> fpsnr;
  if (display) fpsnr = metrics::fpsnr(a, b, *display, gaze_x, gaze_y);
  if (options.json) {
    nlohmann::json out = {{"a", options.a.string()},
                          {"b", options.b.string()},
                          {"mse", psnr.mse},
                          {"identical", psnr.identical},
                          {"ssim", ssim.mean_ssim},
                          {"flip", flip ? nlohmann::json(flip->mean_flip) : nlohmann::json(nullptr)},
                          {"flip_pixels_per_degree", pixels_per_degree}};
    out["psnr_db"] = psnr.identical ? nlohmann::json(nullptr) : nlohmann::json(psnr.psnr_db);
    out["fpsnr_db"] = fpsnr && !fpsnr->identical ? nlohmann::json(fpsnr->fpsnr_db) : nlohmann::json(nullptr);
    if (fpsnr) out["gaze"] = {gaze_x, gaze_y};
    std::printf("%s\n", out.dump(2).c_str());
  } else {
    if (psnr.identical) {
      std::printf("PSNR inf dB (identical)\n");
    } else {
      std::printf("PSNR %.2f dB\n", psnr.psnr_db);
    }
    std::printf("SSIM %.6f\n", ssim.mean_ssim);
    if (flip)
      std::printf("FLIP %.6f (%.1f px/deg%s)\n", flip->mean_flip, pixels_per_degree, display ? "" : ", FLIP's default");
    else std::printf("FLIP n/a (values outside [0, 1]: LDR-FLIP needs display values)\n");
    if (fpsnr && fpsnr->identical) std::printf("FPSNR inf dB (identical)\n");
    else if (fpsnr) std::printf("FPSNR %.2f dB (gaze %.1f, %.1f px)\n", fpsnr->fpsnr_db, gaze_x, gaze_y);
  }
}
}  // namespace

void add_compare_command(CLI::App& app) {
  auto options = std::make_shared<CompareOptions>();
  CLI::App* command = app.add_subcommand(
      "compare", "PSNR, SSIM, FLIP and (given the display) FPSNR between two images of the same size");
  command->add_option("a", options->a, "Reference image")->required();
  command->add_option("b", options->b, "Test image")->required();
  command->add_flag("--json", options->json,
                    "Print JSON (psnr_db and fpsnr_db are null when the images are identical)");
  add_display_flags(*command, options->display, /*required=*/false);
  command->callback([options] { run_compare(*options); });
}

}  // namespace fovlab::app

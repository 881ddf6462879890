// fovlab voronoi --width W --height H [display flags] [--sigma-deg D | --sigma-px S] [--seed N]
//                [--out-sites IMG] [--out-cells IMG]: Bruder et al. 2019's sampling mask (foveation/
// voronoi_mask.h) for a screen, as Figure 1 draws it: the sites as black dots on white, and the
// Voronoi cells in colours with the sites on them. Prints the sites, the iterations and the share of
// the screen's pixels that get a ray with the gaze at the centre.
#include <chrono>
#include <cstdio>
#include <memory>

#include "app/commands.h"
#include "app/display_flags.h"
#include "app/output_options.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "core/number_text.h"
#include "foveation/voronoi_mask.h"

namespace fovlab::app {

namespace {

struct VoronoiOptions {
  int width_px = 0;
  int height_px = 0;
  DisplayFlags display;
  double sigma_deg = 2.5;
  double sigma_px = 0.0;  // 0: from --sigma-deg and the display
  uint64_t seed = 1;
  std::filesystem::path sites_out;
  std::filesystem::path cells_out;
};

// A colour of each cell, far from its neighbours' in most cases (a hash of its index).
float cell_channel(uint32_t cell, int channel) {
  uint64_t state = (uint64_t(cell) << 2) | uint64_t(channel);
  state = (state ^ (state >> 31)) * 0x7fb5d329728ea185ULL;
  state = (state ^ (state >> 27)) * 0x81dadef4bc2dd44dULL;
  return 0.35f + 0.55f * float((state >> 40) & 0xffff) / 65535.0f;
}

void run_voronoi(VoronoiOptions options) {
  if (options.width_px < 1 || options.width_px > 4096 || options.height_px < 1 || options.height_px > 4096)
    throw InputError("--width, --height: expected 1 to 4096 pixels (the mask is twice the screen per axis)");
  if (!options.display.gaze.empty())
    throw InputError("--gaze: the mask is made once, centred; a session shifts it to each gaze sample");
  const std::string assumed_display = default_to_fpt_study_display(options.display);
  const DisplayGeometry display = parse_display(options.display, options.width_px, options.height_px);
  VoronoiMaskSettings settings;
  settings.screen_width_px = options.width_px;
  settings.screen_height_px = options.height_px;
  settings.seed = options.seed;
  if (options.sigma_px > 0.0) {
    settings.density_sigma_px = options.sigma_px;
  } else {
    if (!(options.sigma_deg > 0.0 && options.sigma_deg <= 90.0))
      throw InputError("--sigma-deg: expected a radius in degrees in (0, 90]");
    settings.density_sigma_px = density_sigma_px(display, options.sigma_deg);
  }
  if (!(settings.density_sigma_px > 0.0 && settings.density_sigma_px <= 1e6))
    throw InputError("--sigma-px: expected a radius in pixels in (0, 1e6]");

  const auto start = std::chrono::steady_clock::now();
  const VoronoiMask mask = make_voronoi_mask(settings);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  int on_screen = 0;
  const float x0 = float(options.width_px) / 2, y0 = float(options.height_px) / 2;
  for (const MaskSite& site : mask.sites)
    on_screen += site.x_px >= x0 && site.x_px < x0 + float(options.width_px) && site.y_px >= y0 &&
                 site.y_px < y0 + float(options.height_px);
  std::printf(
      "mask %dx%d for a %dx%d screen, s %.2f px (%s): %zu sites after %d iterations (%s), %.2f s; "
      "%d rays on the screen with the gaze at the centre: %.2f %% of its pixels\n",
      mask.width_px, mask.height_px, options.width_px, options.height_px, settings.density_sigma_px,
      options.sigma_px > 0.0 ? "--sigma-px" : (format_number(options.sigma_deg, 6) + " deg").c_str(), mask.sites.size(),
      mask.iterations, mask.converged ? "converged" : "stopped at the limit", seconds, on_screen,
      100.0 * on_screen / (double(options.width_px) * options.height_px));
  std::printf("%s\n", display_line(display, assumed_display).c_str());

  if (!options.sites_out.empty()) {
    Image sites(mask.width_px, mask.height_px, 1);
    std::fill(sites.pixels.begin(), sites.pixels.end(), 1.0f);
    for (const MaskSite& site : mask.sites) sites.at(int(site.x_px), int(site.y_px), 0) = 0.0f;
    write_image(options.sites_out, sites);
  }
  if (!options.cells_out.empty()) {
    std::vector<MaskSite> sites = mask.sites;
    const std::vector<uint32_t> owner = nearest_sites(sites, mask.width_px, mask.height_px);
    Image cells(mask.width_px, mask.height_px, 3);
    for (int y = 0; y < mask.height_px; ++y)
      for (int x = 0; x < mask.width_px; ++x)
        for (int c = 0; c < 3; ++c)
          cells.at(x, y, c) = cell_channel(owner[size_t(y) * size_t(mask.width_px) + size_t(x)], c);
    for (const MaskSite& site : mask.sites)
      for (int c = 0; c < 3; ++c) cells.at(int(site.x_px), int(site.y_px), c) = 0.0f;
    write_image(options.cells_out, cells);
  }
}

}  // namespace

void add_voronoi_command(CLI::App& app) {
  auto options = std::make_shared<VoronoiOptions>();
  CLI::App* command =
      app.add_subcommand("voronoi", "Bruder et al. 2019's Voronoi sampling mask for a screen (Figure 1)");
  command->add_option("--width", options->width_px, "Screen width in pixels (the mask is twice as wide)")->required();
  command->add_option("--height", options->height_px, "Screen height in pixels")->required();
  add_display_flags(*command, options->display, false);  // default: 27" at 500 mm
  command->add_option("--sigma-deg", options->sigma_deg,
                      "Phi's Gaussian radius in degrees of visual angle (default 2.5)");
  command->add_option("--sigma-px", options->sigma_px, "Phi's Gaussian radius in pixels, instead of --sigma-deg");
  command->add_option("--seed", options->seed, "Seed of the initial sites (default 1)");
  add_output_option(*command, "--out-sites", options->sites_out, "The sites as black dots on white (PNG)",
                    {{OutputKind::image_file}, kReplacesAFile});
  add_output_option(*command, "--out-cells", options->cells_out,
                    "The Voronoi cells in colours, the sites in black (PNG)",
                    {{OutputKind::image_file}, kReplacesAFile});
  command->callback([options] { run_voronoi(*options); });
}

}  // namespace fovlab::app

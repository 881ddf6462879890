#include "app/render_volume.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "app/cli_support.h"
#include "app/render_outputs.h"
#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "foveation/voronoi_reconstruction.h"
#include "renderer/vk/context.h"
#include "renderer/volume/volume_raycaster.h"

namespace fovlab::app {

void run_render_volume(const VolumeRenderOptions& options) {
  if (options.width_px < 1 || options.width_px > kMaxVolumeFrameSidePx || options.height_px < 1 ||
      options.height_px > kMaxVolumeFrameSidePx)
    throw InputError("--width, --height: expected 1 to " + std::to_string(kMaxVolumeFrameSidePx) +
                     " pixels for a volume frame");
  if (options.frames < 1 || options.frames > 100000)
    throw InputError("--frames " + std::to_string(options.frames) + ": expected 1 to 100000");
  if (!(options.frame_rate_hz > 0.0 && std::isfinite(options.frame_rate_hz)))
    throw InputError("--frame-rate: expected a positive number of frames per second");
  if (!(options.step_voxels >= 0.05 && options.step_voxels <= 16.0))
    throw InputError("--step-voxels: expected 0.05 to 16 voxels");
  if (!(options.sigma_deg > 0.0 && options.sigma_deg <= 90.0))
    throw InputError("--sigma-deg: expected a radius in degrees in (0, 90]");
  if (!std::isfinite(options.time_s)) throw InputError("--time: expected a finite scene time in seconds");
  if (!options.mask_out.empty() && !options.foveated)
    throw InputError("--mask-out: only fvolume has a sampling mask; add --method fvolume");
  DisplayFlags display_flags = options.display;
  const std::string assumed_display = default_to_fpt_study_display(display_flags);
  const DisplayGeometry display = parse_display(display_flags, options.width_px, options.height_px);
  const auto [gaze_x, gaze_y] = parse_gaze(display_flags.gaze, options.width_px, options.height_px);

  const VolumeScene scene = load_volume_scene(options.scene);
  vk::Context context(context_options(options.device));
  const VolumeGrid grid = load_scene_volume(scene, volume_limits(context));
  VolumeRaycaster raycaster(context, scene, grid);
  std::optional<VoronoiReconstruction> reconstruction;
  if (options.foveated) {
    const VoronoiMaskSettings mask_settings =
        voronoi_mask_settings(options.width_px, options.height_px, display, options.sigma_deg);
    reconstruction =
        cached_voronoi_reconstruction(mask_settings, kVoronoiCacheFolder, percent_progress("sampling mask weights"));
    raycaster.set_reconstruction(*reconstruction);
  }
  VolumeRenderSettings settings;
  settings.width_px = options.width_px;
  settings.height_px = options.height_px;
  settings.step_voxels = options.step_voxels;
  settings.correct_opacity = options.correct_opacity;
  VolumeFrameResult result;
  std::vector<double> gpu_ms;
  const auto started = std::chrono::steady_clock::now();
  for (int frame = 0; frame < options.frames; ++frame) {
    settings.time_s = options.time_s + frame / options.frame_rate_hz;
    settings.frame_index = uint32_t(frame);
    result = options.foveated ? raycaster.render_foveated(settings, gaze_x, gaze_y, options.smoothing)
                              : raycaster.render_full(settings);
    gpu_ms.push_back(result.gpu_ms);
  }
  const double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  fail_on_validation_messages(context);
  write_colour(options.out, result.colour_linear);
  if (reconstruction && !options.mask_out.empty()) {
    // The traced sites on the screen: black dots on white.
    Image mask(options.width_px, options.height_px, 1);
    std::fill(mask.pixels.begin(), mask.pixels.end(), 1.0f);
    const auto [offset_x, offset_y] = raycaster.mask_offset(options.width_px, options.height_px, gaze_x, gaze_y);
    for (const MaskSite& site : reconstruction->mask.sites) {
      const int x = int(std::floor(site.x_px)) - offset_x, y = int(std::floor(site.y_px)) - offset_y;
      if (x >= 0 && y >= 0 && x < options.width_px && y < options.height_px) mask.at(x, y, 0) = 0.0f;
    }
    write_image(options.mask_out, mask);
  }
  nlohmann::json stats = {{"scene", scene.name},
                          {"method", options.foveated ? "fvolume" : "volume"},
                          {"width", options.width_px},
                          {"height", options.height_px},
                          {"volume_voxels", {grid.size_voxels[0], grid.size_voxels[1], grid.size_voxels[2]}},
                          {"device", context.description.name},
                          {"frames", options.frames},
                          {"gpu_ms", result.gpu_ms},
                          {"gpu_ms_per_frame", gpu_ms},
                          {"reconstruct_gpu_ms", result.reconstruct_gpu_ms},
                          {"wall_ms_per_frame", wall_ms / options.frames},
                          {"rays", result.rays},
                          {"traced_share", result.traced_share}};
  if (reconstruction) stats["sites"] = reconstruction->mask.sites.size();
  if (!options.stats_json.empty()) write_text_atomically(options.stats_json, stats.dump(2) + "\n");
  std::printf("%s %s %dx%d (%dx%dx%d voxels): %.2f ms GPU", scene.name.c_str(), options.foveated ? "fvolume" : "volume",
              options.width_px, options.height_px, grid.size_voxels[0], grid.size_voxels[1], grid.size_voxels[2],
              result.gpu_ms);
  if (options.foveated)
    std::printf(" (reconstruction %.2f ms), %llu rays: %.2f %% of the pixels", result.reconstruct_gpu_ms,
                static_cast<unsigned long long>(result.rays), 100.0 * result.traced_share);
  std::printf(" -> %s\n", options.out.c_str());
  if (options.foveated) std::printf("%s\n", display_line(display, assumed_display).c_str());
}

}  // namespace fovlab::app

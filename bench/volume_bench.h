#pragma once
// Bruder et al. 2019's benchmark (section 5, Table 1) on fovlab's raycaster: for each volume scene, random
// cameras x random gazes (seeded), each configuration the median of `frames` timed frames after one
// untimed; per camera the full frame's GPU time over the median foveated one (the speed-up), then
// summarised per volume as the paper's box plots; with the share of pixels traced, the
// reconstruction's time and the foveated frame's error against the full one (SSIM, FLIP, FPSNR at
// the gaze). `fovlab bench-volume` prints and writes it.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "foveation/display_geometry.h"

namespace fovlab::vk {
class Context;
}

namespace fovlab::bench {

struct VolumeBenchPlan {
  std::vector<std::string> scenes;  // built-in names or .toml volume scenes
  int width_px = 512, height_px = 512;
  int cameras = 8;  // random orbits: azimuth 0-360, elevation -60 to 60 degrees
  int gazes = 4;    // random gaze positions on the screen, per camera
  int frames = 5;   // timed frames a configuration (median)
  uint64_t seed = 1;
  double sigma_deg = 2.5;  // the sampling density's Gaussian radius
  bool correct_opacity = true;
  DisplayGeometry display;  // the frame's: its pixels at the display's pitch (frame_on_display)
  DisplayGeometry screen;   // the whole display the frame is centred on, for the record (width_px 0: display)
  bool trace_read_sites_only = true;  // false: the earlier rule, every site within one global reach
  std::string voronoi_cache;          // folder of the masks' cache
};

// A frame of frame_width_px x frame_height_px pixels centred on `screen` (the eye on the
// perpendicular through its centre): the frame's pixels have the screen's pitch, so its millimetres
// are its pixels times the pitch. InputError naming --width/--height when the frame is larger than
// the screen.
DisplayGeometry frame_on_display(const DisplayGeometry& screen, int frame_width_px, int frame_height_px);

struct VolumeBenchCamera {
  double azimuth_deg = 0.0, elevation_deg = 0.0;
  double full_ms = 0.0;           // median GPU ms of the full frame
  double foveated_ms = 0.0;       // median over the gazes of each gaze's median
  double reconstruct_ms = 0.0;    // the same, of the reconstruction alone
  double traced_share = 0.0;      // mean over the gazes
  double sites_on_screen = 0.0;   // mean over the gazes: the mask's sites that lie on the screen
  double traced_rays = 0.0;       // mean over the gazes: the rays traced (rays = traced_share x pixels)
  double speed_up = 0.0;          // full_ms / foveated_ms
  double ssim = 0.0, flip = 0.0;  // means over the gazes
  double fpsnr_db = 0.0;          // mean over the gazes of finite values
};

struct VolumeBenchResult {
  std::string scene;
  std::vector<int> volume_voxels;
  size_t sites = 0;
  double fovea_sigma_px = 0.0;  // the density's Gaussian radius s in the frame's pixels (at the display's centre)
  std::vector<VolumeBenchCamera> cameras;
  // Over the cameras: quartiles of the speed-up, medians of the rest.
  double speed_up_min = 0, speed_up_q1 = 0, speed_up_median = 0, speed_up_q3 = 0, speed_up_max = 0;
  double full_ms = 0, foveated_ms = 0, reconstruct_ms = 0, traced_share = 0, ssim = 0, flip = 0, fpsnr_db = 0;
  double sites_on_screen = 0, traced_rays = 0;
};

// Runs the plan (InputError for a bad scene or size). `progress` gets a line a camera.
std::vector<VolumeBenchResult> run_volume_bench(vk::Context& context, const VolumeBenchPlan& plan,
                                                void (*progress)(const std::string& line) = nullptr);

// The Markdown table, the JSON and the box plot (SVG) of the results.
std::string volume_bench_markdown(const std::vector<VolumeBenchResult>& results);
nlohmann::json volume_bench_json(const VolumeBenchPlan& plan, const std::vector<VolumeBenchResult>& results);
std::string volume_bench_svg(const std::vector<VolumeBenchResult>& results);

}  // namespace fovlab::bench

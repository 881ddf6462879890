#pragma once
// `fovlab render --method volume|fvolume`: Bruder et al. 2019's volume raycaster, every pixel (volume) or
// foveated on the Voronoi sampling mask (fvolume), one frame or a sequence (the temporal smoothing
// averages a sequence's frames while the view stays and the gaze moves).
#include <filesystem>
#include <string>

#include "app/display_flags.h"

namespace fovlab::app {

struct VolumeRenderOptions {
  std::string scene;  // a built-in volume scene or a .toml volume scene
  bool foveated = false;
  int width_px = 0, height_px = 0;
  double time_s = 0.0;
  int frames = 1;
  double frame_rate_hz = 60.0;
  DisplayFlags display;  // fvolume: the display (Polychronakis et al. 2021's by default) and --gaze
  double sigma_deg = 2.5;
  double step_voxels = 0.5;
  bool correct_opacity = true;
  bool smoothing = true;
  std::string device;
  std::filesystem::path out, mask_out, stats_json;
};

void run_render_volume(const VolumeRenderOptions& options);

}  // namespace fovlab::app

#pragma once
// Step-count heat maps as in Polychronakis et al. 2023 Fig. 4: blue for 1 step, red for the step cap, on a log scale,
// so GT and IPR frames of any spp are drawn on one scale (steps per sample).
#include "core/image.h"

namespace fovlab {

// `steps_per_pixel`: one channel. Returns sRGB-encoded RGB, ready for a PNG.
Image step_heatmap(const Image& steps_per_pixel, int samples_per_pixel, int max_steps);

}  // namespace fovlab

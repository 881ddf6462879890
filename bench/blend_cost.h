#pragma once
// The cost of the zone blend (renderer/zone_blend) against the memory-bandwidth limit it is measured
// by: a plain copy of one full-size float RGBA zone buffer into another (every pixel read once and
// written once, the least a blend must do), the baseline of `fovlab blend --repeats` and `fovlab
// bench-fpt` (bench/fpt_timing.h).
#include <cstdint>
#include <vector>

#include "foveation/display_geometry.h"
#include "foveation/zone_layout.h"

namespace fovlab {
class ZoneBlender;
}  // namespace fovlab

namespace fovlab::bench {

struct BlendCost {
  double display_blend_ms = 0;
  double linear_blend_ms = 0;
  double copy_shader_ms = 0;
  double copy_buffer_ms = 0;
  uint32_t band_pixels = 0;
};

// Each repeat is one command buffer holding, between GPU timestamps, the display blend
// (display_frame's passes, sRGB8 out), the linear blend (float RGBA out), a copy shader
// (buffer_copy.comp.glsl: one load and one store a texel, the blend's workgroups) and
// vkCmdCopyBuffer of the same buffer. One entry a repeat; zeros where the queue has no timestamps.
// Also the number of band pixels, which the display blend's second pass blends. Needs a colour
// frame in `blender`, as display_frame does (InputError otherwise).
std::vector<BlendCost> measure_blend_cost(ZoneBlender& blender, const DisplayGeometry& display, double gaze_x_px,
                                          double gaze_y_px, const ZoneBounds& bounds, int repeats);

}  // namespace fovlab::bench

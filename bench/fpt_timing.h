#pragma once
// Timing the emulated foveated path tracer's GPU work (docs/foveated-path-tracing.md), shared by
// `fovlab upsample --repeats`, `fovlab blend --repeats` and `fovlab bench-fpt`, so that each figure
// is measured one way: medians of repeated runs, the baselines timed in the same run.
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "foveation/display_geometry.h"
#include "renderer/upsampling/upsample_filter.h"
#include "foveation/zone_layout.h"

namespace fovlab {
class Upsampler;
class ZoneBlender;
}  // namespace fovlab

namespace fovlab::bench {

struct UpsampleTiming {
  Image upsampled;           // the GPU's image (of the last run)
  double gpu_median_ms = 0;  // both passes, GPU timestamps
  int repeats = 0;
  // With against_openimageio (Lanczos-3 only): OpenImageIO's resize of the same image on the CPU,
  // every core, wall clock; the largest absolute differences between the three results.
  bool against_openimageio = false;
  double openimageio_median_ms = 0;
  double gpu_vs_reference = 0, openimageio_vs_reference = 0, gpu_vs_openimageio = 0;
  double input_low = 0, input_high = 0;  // the input's value range, to read the differences by
  nlohmann::json json() const;
};

// `repeats` GPU upsamplings of `image` (and as many OpenImageIO resizes after them).
UpsampleTiming time_upsampling(Upsampler& upsampler, const Image& image, int factor, UpsampleFilter filter, int repeats,
                               bool against_openimageio);

struct BlendTiming {
  // GPU medians (ms) of measure_blend_cost's four passes (bench/blend_cost.h).
  double display_blend_ms = 0, linear_blend_ms = 0, copy_shader_ms = 0, copy_buffer_ms = 0;
  // A session's refresh on the wall clock: ZoneBlender::display_frame (blend, encode, read back).
  double refresh_wall_ms = 0;
  int repeats = 0;
  uint32_t band_pixels = 0, frame_pixels = 0;  // the display blend's second pass blends the band pixels
  nlohmann::json json() const;
};

// The blend of `blender`'s current frame for one gaze, `repeats` times each way.
BlendTiming time_blend(ZoneBlender& blender, const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                       const ZoneBounds& bounds, int repeats);

// The median GPU ms of `repeats` ZoneBlender::set_frame calls for `frame`: what one animation frame's
// zone buffers cost (upsampling, and the sRGB8 encoding of the three zones).
double time_zone_buffers(ZoneBlender& blender, const Image& frame, int repeats);

// The lines `fovlab blend --repeats` and `fovlab bench-fpt` print.
void print_blend_timing(const BlendTiming& timing);

}  // namespace fovlab::bench

#include "bench/fpt_timing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "bench/bench_runs.h"  // median, elapsed_ms
#include "bench/blend_cost.h"
#include "bench/openimageio_resize.h"
#include "renderer/upsampling/upsampler.h"
#include "renderer/zone_blend/zone_blender.h"

namespace fovlab::bench {

namespace {

double largest_difference(const Image& a, const Image& b) {
  double largest = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i)
    largest = std::max(largest, double(std::fabs(a.pixels[i] - b.pixels[i])));
  return largest;
}

}  // namespace

UpsampleTiming time_upsampling(Upsampler& upsampler, const Image& image, int factor, UpsampleFilter filter, int repeats,
                               bool against_openimageio) {
  UpsampleTiming timing;
  timing.repeats = repeats;
  std::vector<double> gpu_ms;
  for (int run = 0; run < repeats; ++run) {
    UpsampleResult result = upsampler.upsample(image, factor, filter);
    gpu_ms.push_back(result.gpu_ms);
    timing.upsampled = std::move(result.image);
  }
  timing.gpu_median_ms = median(gpu_ms);
  if (!against_openimageio) return timing;
  timing.against_openimageio = true;
  std::vector<double> openimageio_ms;
  Image resized;
  for (int run = 0; run < repeats; ++run) {
    const auto started = std::chrono::steady_clock::now();
    resized = resize_with_openimageio(image, factor);
    openimageio_ms.push_back(elapsed_ms(started));
  }
  timing.openimageio_median_ms = median(openimageio_ms);
  const Image reference = upsample_reference(image, factor, filter);
  timing.gpu_vs_reference = largest_difference(timing.upsampled, reference);
  timing.openimageio_vs_reference = largest_difference(resized, reference);
  timing.gpu_vs_openimageio = largest_difference(timing.upsampled, resized);
  const auto [low, high] = std::minmax_element(image.pixels.begin(), image.pixels.end());
  timing.input_low = *low;
  timing.input_high = *high;
  return timing;
}

nlohmann::json UpsampleTiming::json() const {
  nlohmann::json out = {{"gpu_median_ms", gpu_median_ms}, {"repeats", repeats}};
  if (against_openimageio) {
    out["openimageio_median_wall_ms"] = openimageio_median_ms;
    out["gpu_over_openimageio"] = gpu_median_ms / openimageio_median_ms;
    out["largest_difference"] = {{"gpu_vs_reference", gpu_vs_reference},
                                 {"openimageio_vs_reference", openimageio_vs_reference},
                                 {"gpu_vs_openimageio", gpu_vs_openimageio}};
    out["input_range"] = {input_low, input_high};
  }
  return out;
}

BlendTiming time_blend(ZoneBlender& blender, const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                       const ZoneBounds& bounds, int repeats) {
  std::vector<double> display_ms, linear_ms, shader_ms, buffer_ms, refresh_ms;
  uint32_t band_pixels = 0;
  for (const BlendCost& cost : measure_blend_cost(blender, display, gaze_x_px, gaze_y_px, bounds, repeats)) {
    band_pixels = cost.band_pixels;
    display_ms.push_back(cost.display_blend_ms);
    linear_ms.push_back(cost.linear_blend_ms);
    shader_ms.push_back(cost.copy_shader_ms);
    buffer_ms.push_back(cost.copy_buffer_ms);
  }
  for (int run = 0; run < repeats; ++run) {
    const auto started = std::chrono::steady_clock::now();
    blender.display_frame(display, gaze_x_px, gaze_y_px, bounds);
    refresh_ms.push_back(elapsed_ms(started));
  }
  return {
      median(display_ms), median(linear_ms), median(shader_ms), median(buffer_ms),
      median(refresh_ms), repeats,           band_pixels,       uint32_t(blender.width()) * uint32_t(blender.height())};
}

double time_zone_buffers(ZoneBlender& blender, const Image& frame, int repeats) {
  std::vector<double> gpu_ms;
  for (int run = 0; run < repeats; ++run) gpu_ms.push_back(blender.set_frame(frame));
  return median(gpu_ms);
}

nlohmann::json BlendTiming::json() const {
  return {{"display_blend_gpu_ms", display_blend_ms},
          {"linear_blend_gpu_ms", linear_blend_ms},
          {"copy_shader_gpu_ms", copy_shader_ms},
          {"copy_buffer_gpu_ms", copy_buffer_ms},
          {"display_blend_over_copy_shader", display_blend_ms / copy_shader_ms},
          {"display_blend_over_copy_buffer", display_blend_ms / copy_buffer_ms},
          {"linear_blend_over_copy_shader", linear_blend_ms / copy_shader_ms},
          {"linear_blend_over_copy_buffer", linear_blend_ms / copy_buffer_ms},
          {"refresh_wall_ms", refresh_wall_ms},
          {"band_pixels", band_pixels},
          {"frame_pixels", frame_pixels},
          {"repeats", repeats}};
}

void print_blend_timing(const BlendTiming& timing) {
  std::printf("GPU medians of %d runs (ms), against a copy of one full-size float RGBA buffer:\n", timing.repeats);
  std::printf("  blend to the sRGB8 frame (sessions)  %9.3f  %5.2fx the copy shader  %5.2fx vkCmdCopyBuffer\n",
              timing.display_blend_ms, timing.display_blend_ms / timing.copy_shader_ms,
              timing.display_blend_ms / timing.copy_buffer_ms);
  std::printf("  blend to float RGBA (previews)       %9.3f  %5.2fx the copy shader  %5.2fx vkCmdCopyBuffer\n",
              timing.linear_blend_ms, timing.linear_blend_ms / timing.copy_shader_ms,
              timing.linear_blend_ms / timing.copy_buffer_ms);
  std::printf("  copy shader (buffer_copy)            %9.3f\n", timing.copy_shader_ms);
  std::printf("  vkCmdCopyBuffer                      %9.3f\n", timing.copy_buffer_ms);
  std::printf("Band pixels (the display blend's second pass): %u of %u (%.1f %%)\n", timing.band_pixels,
              timing.frame_pixels, 100.0 * timing.band_pixels / std::max(1u, timing.frame_pixels));
  std::printf("A session's refresh (sRGB8 blend, read back to the CPU): median %.3f ms wall of %d\n",
              timing.refresh_wall_ms, timing.repeats);
}

}  // namespace fovlab::bench

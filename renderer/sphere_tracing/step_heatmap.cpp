#include "renderer/sphere_tracing/step_heatmap.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace fovlab {

namespace {
// Blue -> cyan -> green -> yellow -> red, sRGB-encoded control points at equal spacing.
constexpr std::array<std::array<float, 3>, 5> kRamp = {
    {{0.0f, 0.0f, 1.0f}, {0.0f, 1.0f, 1.0f}, {0.0f, 1.0f, 0.0f}, {1.0f, 1.0f, 0.0f}, {1.0f, 0.0f, 0.0f}}};
}  // namespace

Image step_heatmap(const Image& steps_per_pixel, int samples_per_pixel, int max_steps) {
  Image heatmap(steps_per_pixel.width, steps_per_pixel.height, 3);
  const double log_cap = std::log(static_cast<double>(std::max(max_steps, 2)));
  for (size_t p = 0; p < steps_per_pixel.pixel_count(); ++p) {
    const double steps_per_sample = steps_per_pixel.pixels[p] / static_cast<double>(samples_per_pixel);
    if (steps_per_sample <= 0.0) continue;  // no steps at all (ray never entered the scene bounds): black
    const double position = std::clamp(std::log(std::max(steps_per_sample, 1.0)) / log_cap, 0.0, 1.0);
    const double scaled = position * static_cast<double>(kRamp.size() - 1);
    const size_t segment = std::min(static_cast<size_t>(scaled), kRamp.size() - 2);
    const float fraction = static_cast<float>(scaled - static_cast<double>(segment));
    for (size_t c = 0; c < 3; ++c) {
      heatmap.pixels[p * 3 + c] = kRamp[segment][c] + fraction * (kRamp[segment + 1][c] - kRamp[segment][c]);
    }
  }
  return heatmap;
}

}  // namespace fovlab

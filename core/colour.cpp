#include "core/colour.h"

#include <algorithm>
#include <cmath>

namespace fovlab {

float encode_srgb(float linear) {
  const float value = std::clamp(std::isnan(linear) ? 0.0f : linear, 0.0f, 1.0f);
  return value <= 0.0031308f ? 12.92f * value : 1.055f * std::pow(value, 1.0f / 2.4f) - 0.055f;
}

Image encode_srgb(const Image& linear) {
  Image encoded = linear;
  const bool has_alpha = linear.channels == 4;
  for (size_t i = 0; i < encoded.pixels.size(); ++i) {
    const bool is_alpha = has_alpha && i % 4 == 3;
    if (!is_alpha) encoded.pixels[i] = encode_srgb(linear.pixels[i]);
  }
  return encoded;
}

}  // namespace fovlab

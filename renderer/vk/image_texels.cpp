#include "renderer/vk/image_texels.h"

#include <cstddef>

namespace fovlab::vk {

void pack_rgba_texels(const Image& image, float* texels) {
  const size_t channels = size_t(image.channels);
  for (size_t p = 0; p < image.pixel_count(); ++p)
    for (size_t c = 0; c < 4; ++c) texels[p * 4 + c] = c < channels ? image.pixels[p * channels + c] : 0.0f;
}

Image unpack_rgba_texels(const float* texels, int width, int height, int channels) {
  Image image(width, height, channels);
  for (size_t p = 0; p < image.pixel_count(); ++p)
    for (size_t c = 0; c < size_t(channels); ++c) image.pixels[p * size_t(channels) + c] = texels[p * 4 + c];
  return image;
}

}  // namespace fovlab::vk

#pragma once
// CPU images (1 to 4 float channels) to and from the RGBA float texels (16 bytes a pixel) of the
// storage buffers the image passes read and write; missing channels are written as 0.
#include "core/image.h"

namespace fovlab::vk {

void pack_rgba_texels(const Image& image, float* texels);
Image unpack_rgba_texels(const float* texels, int width, int height, int channels);

}  // namespace fovlab::vk

#pragma once
// Colour encodings. Renders are linear light; PNGs and the image metrics use sRGB-encoded values.
#include "core/image.h"

namespace fovlab {

// IEC 61966-2-1 sRGB transfer function of one linear value, clamped to [0, 1] first.
float encode_srgb(float linear);

// Every colour channel encoded (alpha, if any, copied), so the image can be written as a PNG.
Image encode_srgb(const Image& linear);

}  // namespace fovlab

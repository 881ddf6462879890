#pragma once
// The input checks every image metric makes (PSNR, SSIM, FLIP, FPSNR), with one wording:
// std::invalid_argument for a layout that is not grey, RGB or RGBA of width x height pixels, and
// for two images of different sizes.
#include <stdexcept>
#include <string>

#include "core/image.h"

namespace fovlab::metrics::detail {

inline std::string size_text(const Image& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height);
}

// The colour channels a metric compares: alpha is not a colour.
inline int colour_channel_count(const Image& image) { return image.channels == 4 ? 3 : image.channels; }

inline void require_valid_layout(const Image& image) {
  if (image.channels != 1 && image.channels != 3 && image.channels != 4) {
    throw std::invalid_argument("image has " + std::to_string(image.channels) +
                                " channels; expected 1 (grey), 3 (RGB) or 4 (RGBA)");
  }
  if (image.width < 0 || image.height < 0 ||
      image.pixels.size() != image.pixel_count() * static_cast<std::size_t>(image.channels)) {
    throw std::invalid_argument("image " + size_text(image) + "x" + std::to_string(image.channels) + " has " +
                                std::to_string(image.pixels.size()) + " values; expected width * height * channels");
  }
}

inline void require_same_size(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("images differ in size: " + size_text(a) + " vs " + size_text(b));
}

}  // namespace fovlab::metrics::detail

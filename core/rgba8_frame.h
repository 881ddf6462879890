#pragma once
// What a display shows (display/presenter.h): 8-bit sRGB-encoded RGBA, row-major, top row first, alpha 255.
#include <cstdint>
#include <vector>

namespace fovlab {

struct Rgba8Frame {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4 bytes

  Rgba8Frame() = default;
  Rgba8Frame(int width_px, int height_px)
      : width(width_px),
        height(height_px),
        rgba(static_cast<size_t>(width_px) * static_cast<size_t>(height_px) * 4, 0) {
    for (size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 255;
  }
};

}  // namespace fovlab

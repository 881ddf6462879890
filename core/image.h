#pragma once
// A plain CPU image: interleaved float channels, row-major, top row first.
// Colour images produced for display hold sRGB-encoded values in [0, 1];
// linear-light buffers (EXR) hold linear values. The producer says which.
#include <cstddef>
#include <vector>

namespace fovlab {

struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;           // 1 (grey), 3 (RGB) or 4 (RGBA)
  std::vector<float> pixels;  // width * height * channels values

  Image() = default;
  Image(int width_px, int height_px, int channel_count)
      : width(width_px),
        height(height_px),
        channels(channel_count),
        pixels(static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px) *
               static_cast<std::size_t>(channel_count)) {}

  std::size_t pixel_count() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  float& at(int x, int y, int c) {
    return pixels[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) *
                      static_cast<std::size_t>(channels) +
                  static_cast<std::size_t>(c)];
  }
  float at(int x, int y, int c) const {
    return pixels[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) *
                      static_cast<std::size_t>(channels) +
                  static_cast<std::size_t>(c)];
  }
};

}  // namespace fovlab

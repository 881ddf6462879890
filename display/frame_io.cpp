#include "display/frame_io.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/image_io.h"

namespace fovlab {

Image frame_to_image(const Rgba8Frame& frame) {
  Image image(frame.width, frame.height, 4);
  std::transform(frame.rgba.begin(), frame.rgba.end(), image.pixels.begin(),
                 [](uint8_t byte) { return static_cast<float>(byte) / 255.0f; });
  return image;
}

Rgba8Frame image_to_frame(const Image& image) {
  if (image.channels != 1 && image.channels != 3 && image.channels != 4) {
    throw std::invalid_argument("image_to_frame: expected 1, 3 or 4 channels, got " + std::to_string(image.channels));
  }
  Rgba8Frame frame(image.width, image.height);
  auto byte = [](float value) { return static_cast<uint8_t>(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f)); };
  for (size_t i = 0; i < image.pixel_count(); ++i) {
    const float* in = image.pixels.data() + i * static_cast<size_t>(image.channels);
    uint8_t* out = frame.rgba.data() + i * 4;
    for (int c = 0; c < 3; ++c) out[c] = byte(in[image.channels == 1 ? 0 : c]);
    out[3] = image.channels == 4 ? byte(in[3]) : 255;
  }
  return frame;
}

void write_frame_image(const std::filesystem::path& path, const Rgba8Frame& frame) {
  write_image(path, frame_to_image(frame));
}

}  // namespace fovlab

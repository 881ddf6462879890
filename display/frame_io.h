#pragma once
// Rgba8Frame <-> core Image, to save what a presenter showed (screenshots, text screens) as PNG.
#include <filesystem>

#include "core/image.h"
#include "core/rgba8_frame.h"

namespace fovlab {

// Four channels, values byte / 255 (still sRGB-encoded), so write_image's 8-bit PNG is exact.
Image frame_to_image(const Rgba8Frame& frame);

// The inverse (values clamped to [0, 1] and rounded); a 1- or 3-channel image gets alpha 255.
Rgba8Frame image_to_frame(const Image& image);

// write_image (core/image_io.h) of frame_to_image (format by extension; .png is exact): atomic, InputError when it cannot be written.
void write_frame_image(const std::filesystem::path& path, const Rgba8Frame& frame);

}  // namespace fovlab

#pragma once
// Image files through OpenImageIO. Writes never leave a half-written file: the image goes to a
// temporary name in the same folder, then is renamed over the target.
#include <filesystem>
#include <string>

#include "core/image.h"

namespace fovlab {

// The extension of `path`, lower-case, with its dot (".exr").
std::string lower_extension(const std::filesystem::path& path);

// Reads any format OpenImageIO knows; 8-bit files come back as values in [0, 1]. Throws InputError
// naming the path when the file is missing or unreadable.
Image read_image(const std::filesystem::path& path);

// Writes by extension: .png/.jpg/... as 8 bits per channel (values clamped to [0, 1] and rounded),
// .exr as 32-bit float, with no write time in it (the same pixels give the same bytes). Throws
// InputError naming the path when it cannot be written.
void write_image(const std::filesystem::path& path, const Image& image);

}  // namespace fovlab

#pragma once
// Image files through OpenImageIO. Writes never leave a half-written file: the image goes to a
// temporary name in the same folder, then is renamed over the target.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "core/image.h"

namespace fovlab {

// The extension of `path`, lower-case, with its dot (".exr").
std::string lower_extension(const std::filesystem::path& path);

// Image files a user names or a cache holds: at most 1 GiB (a 4096x4096 RGBA float EXR is 256 MiB),
// at most 16384 pixels a side, and the decoded pixels (4 bytes a channel) within the memory available.
inline constexpr uint64_t kMaxImageFileBytes = uint64_t(1) << 30;
inline constexpr int kMaxImageSidePx = 16384;
inline constexpr const char* kImageFileExpected = "a PNG, EXR or other image file OpenImageIO reads";

// Reads an image file through the input guard (core/input_file.h: a regular file, at most
// kMaxImageFileBytes), then decode_image. 8-bit files come back as values in [0, 1]. Throws a one-line
// InputError naming the path when the file is missing, not a regular file, too large, claims more
// pixels than the caps above, or does not decode.
Image read_image(const std::filesystem::path& path);

// An image from a file's bytes, by the format `name`'s extension names (name: the file, for the
// format and for messages; OpenImageIO never opens it). The header's width, height and channels are
// checked before any pixel is allocated.
Image decode_image(std::string_view bytes, const std::string& name);

// Writes by extension: .png/.jpg/... as 8 bits per channel (values clamped to [0, 1] and rounded),
// .exr as 32-bit float, with no write time in it (the same pixels give the same bytes). Throws
// InputError naming the path when it cannot be written.
void write_image(const std::filesystem::path& path, const Image& image);

// The step write_image takes inside write_atomically (core/atomic_file.h): the image written to
// `temporary` as it is (no rename), in the format of `target`'s extension, errors naming `target`; for
// a caller that acts between the write and the rename (the frame cache hashes the bytes first).
void write_image_to_temporary(const std::filesystem::path& temporary, const Image& image,
                              const std::filesystem::path& target);

}  // namespace fovlab

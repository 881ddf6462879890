#pragma once
// Image files through OpenImageIO, which reads and writes memory only: the bytes of a file are read
// through the input guard (core/input_file.h) and written by core/atomic_file.h, whole or not at all.
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

// The file's bytes of `image` in the format of `target`'s extension (OpenImageIO writes nothing to
// disk): .png/.jpg/... as 8 bits per channel (values clamped to [0, 1] and rounded), .exr as 32-bit
// float with no write time in it (the same pixels give the same bytes). Throws InputError naming
// `target` for a format OpenImageIO cannot write to memory (can_encode_image) or an encoding error.
std::string encode_image(const Image& image, const std::filesystem::path& target);
bool can_encode_image(const std::filesystem::path& target);

// encode_image, then write_text_atomically (core/atomic_file.h): the file appears whole or not at
// all, and a failed write (a full disk) throws FileError with the system's reason.
void write_image(const std::filesystem::path& path, const Image& image);

}  // namespace fovlab

#include "core/image_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <memory>
#include <string>

#include "core/atomic_file.h"
#include "core/input_error.h"
#include "core/input_file.h"
#include "core/memory_budget.h"

namespace fovlab {

std::string lower_extension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

namespace {

// OpenImageIO's messages can hold line breaks; a refusal is one line.
std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

}  // namespace

Image decode_image(std::string_view bytes, const std::string& name) {
  const std::string expected = "expected " + std::string(kImageFileExpected);
  const std::string extension = lower_extension(name);
  const std::string format = extension.empty() ? std::string() : extension.substr(1);
  // The plugin by its format's name opens nothing; it then reads these bytes only (an IOProxy), so
  // OpenImageIO never opens a path (a FIFO or a device would block it or feed it without end).
  std::unique_ptr<OIIO::ImageInput> input = format.empty() ? nullptr : OIIO::ImageInput::create(format);
  if (!input) throw InputError(name + ": unknown image format \"" + extension + "\": " + expected);
  if (!input->supports("ioproxy"))
    throw InputError(name + ": OpenImageIO reads \"" + extension + "\" files only by their path: " + expected);
  OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
  input->set_ioproxy(&proxy);
  OIIO::ImageSpec spec;
  if (!input->open(name, spec))
    throw InputError(name + ": cannot read image (" + one_line(input->geterror()) + "): " + expected);
  // The header's sizes, checked before a pixel is allocated: a 30-byte PNG may claim 65535x65535.
  const std::string size = std::to_string(spec.width) + "x" + std::to_string(spec.height);
  if (spec.width < 1 || spec.height < 1 || spec.width > kMaxImageSidePx || spec.height > kMaxImageSidePx)
    throw InputError(name + ": " + size + " pixels in its header: expected 1 to " + std::to_string(kMaxImageSidePx) +
                     " pixels a side");
  if (spec.depth != 1 || spec.nchannels < 1)
    throw InputError(name + ": " + std::to_string(spec.depth) + " slices of " + std::to_string(spec.nchannels) +
                     " channels in its header: expected a 2-D image of 1 or more channels");
  const uint64_t pixel_bytes = uint64_t(spec.width) * uint64_t(spec.height) * uint64_t(spec.nchannels) * sizeof(float);
  check_memory_fits(pixel_bytes, name + ": " + size + " pixels of " + std::to_string(spec.nchannels) + " channels",
                    "expected an image that fits");
  Image image(spec.width, spec.height, spec.nchannels);
  if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data()))
    throw InputError(name + ": cannot decode image (" + one_line(input->geterror()) + "): " + expected);
  return image;
}

Image read_image(const std::filesystem::path& path) {
  return decode_image(read_input_file(path, kImageFileExpected, kMaxImageFileBytes), path.string());
}

void write_image_to_temporary(const std::filesystem::path& temporary, const Image& image,
                              const std::filesystem::path& target) {
  const bool floating_point = lower_extension(target) == ".exr";
  const OIIO::TypeDesc file_type = floating_point ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
  auto output = OIIO::ImageOutput::create(temporary.string());
  if (!output) {
    throw InputError(target.string() + ": cannot write image (" + OIIO::geterror() +
                     "); expected a .png, .exr or other OpenImageIO extension");
  }
  OIIO::ImageSpec spec(image.width, image.height, image.channels, file_type);
  // No write time in the file (OpenEXR's capDate would be the clock's): the same pixels give the
  // same bytes, so a frame cache's hashes hold across machines and runs.
  if (floating_point) spec.attribute("DateTime", "");
  if (!output->open(temporary.string(), spec) ||
      !output->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data()) || !output->close()) {
    throw InputError(target.string() + ": cannot write image: " + output->geterror());
  }
}

void write_image(const std::filesystem::path& path, const Image& image) {
  write_atomically(path, [&](const std::filesystem::path& temporary) { write_image_to_temporary(temporary, image, path); });
}

}  // namespace fovlab

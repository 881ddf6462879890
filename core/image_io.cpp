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
  // The proxy outlives the plugin (declared first): a plugin closed by its destructor, after a
  // refusal below, still reads from a live proxy.
  OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
  std::unique_ptr<OIIO::ImageInput> input = format.empty() ? nullptr : OIIO::ImageInput::create(format);
  if (!input) throw InputError(name + ": unknown image format \"" + extension + "\": " + expected);
  if (!input->supports("ioproxy"))
    throw InputError(name + ": OpenImageIO reads \"" + extension + "\" files only by their path: " + expected);
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

bool can_encode_image(const std::filesystem::path& target) {
  const auto output = OIIO::ImageOutput::create(target.string());
  return output && output->supports("ioproxy");
}

std::string encode_image(const Image& image, const std::filesystem::path& target) {
  const std::string expected = "expected a .png, .exr or other extension OpenImageIO writes to memory";
  // The bytes and their proxy outlive the plugin (declared first): a plugin closed by its
  // destructor after an error still writes into live memory.
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  auto output = OIIO::ImageOutput::create(target.string());
  if (!output)
    throw InputError(target.string() + ": cannot write image (" + one_line(OIIO::geterror()) + "); " + expected);
  if (!output->supports("ioproxy"))
    throw InputError(target.string() + ": OpenImageIO writes \"" + lower_extension(target) +
                     "\" files only by their path; " + expected);
  const bool floating_point = lower_extension(target) == ".exr";
  OIIO::ImageSpec spec(image.width, image.height, image.channels,
                       floating_point ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  // No write time in the file (OpenEXR's capDate would be the clock's): the same pixels give the
  // same bytes, so a frame cache's hashes hold across machines and runs.
  if (floating_point) spec.attribute("DateTime", "");
  // Encoded into memory (an IOProxy): OpenImageIO's writers do not all report a failed write(2) (a
  // PNG on a full disk came out as an empty file and exit 0); the caller writes these bytes itself.
  output->set_ioproxy(&proxy);
  if (!output->open(target.string(), spec) || !output->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data()) ||
      !output->close())
    throw InputError(target.string() + ": cannot encode image: " + one_line(output->geterror()));
  if (bytes.empty()) throw InputError(target.string() + ": OpenImageIO encoded no bytes; " + expected);
  return std::string(bytes.begin(), bytes.end());
}

void write_image(const std::filesystem::path& path, const Image& image) {
  write_text_atomically(path, encode_image(image, path));
}

}  // namespace fovlab

#include "core/image_io.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <string>

#include "core/atomic_file.h"
#include "core/input_error.h"

namespace fovlab {

std::string lower_extension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

Image read_image(const std::filesystem::path& path) {
  auto input = OIIO::ImageInput::open(path.string());
  if (!input) {
    throw InputError(path.string() + ": cannot read image (" + OIIO::geterror() +
                     "); expected an existing PNG, EXR or other OpenImageIO format");
  }
  const OIIO::ImageSpec& spec = input->spec();
  Image image(spec.width, spec.height, spec.nchannels);
  if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data())) {
    throw InputError(path.string() + ": cannot decode image: " + input->geterror());
  }
  return image;
}

void write_image(const std::filesystem::path& path, const Image& image) {
  const bool floating_point = lower_extension(path) == ".exr";
  const OIIO::TypeDesc file_type = floating_point ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
  write_atomically(path, [&](const std::filesystem::path& temporary) {
    auto output = OIIO::ImageOutput::create(temporary.string());
    if (!output) {
      throw InputError(path.string() + ": cannot write image (" + OIIO::geterror() +
                       "); expected a .png, .exr or other OpenImageIO extension");
    }
    OIIO::ImageSpec spec(image.width, image.height, image.channels, file_type);
    // No write time in the file (OpenEXR's capDate would be the clock's): the same pixels give the
    // same bytes, so a frame cache's hashes hold across machines and runs.
    if (floating_point) spec.attribute("DateTime", "");
    if (!output->open(temporary.string(), spec) ||
        !output->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data()) || !output->close()) {
      throw InputError(path.string() + ": cannot write image: " + output->geterror());
    }
  });
}

}  // namespace fovlab

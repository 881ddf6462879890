#include "bench/openimageio_resize.h"

#include <OpenImageIO/imagebufalgo.h>

#include "core/input_error.h"

namespace fovlab::bench {

Image resize_with_openimageio(const Image& image, int factor) {
  const OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::FLOAT);
  const OIIO::ImageBuf source(spec, const_cast<float*>(image.pixels.data()));  // read only
  const OIIO::ROI roi(0, image.width * factor, 0, image.height * factor, 0, 1, 0, image.channels);
  const OIIO::ImageBuf resized = OIIO::ImageBufAlgo::resize(source, "lanczos3", 0.0f, roi);
  if (resized.has_error()) throw InputError("OpenImageIO resize: " + resized.geterror());
  Image out(image.width * factor, image.height * factor, image.channels);
  resized.get_pixels(roi, OIIO::TypeDesc::FLOAT, out.pixels.data());
  return out;
}

}  // namespace fovlab::bench

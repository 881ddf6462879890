#pragma once
// OpenImageIO's own Lanczos-3 resize of a zone buffer, the CPU baseline that `fovlab upsample
// --against-oiio` and `fovlab bench-fpt` time and compare with (bench/fpt_timing.h;
// docs/foveated-path-tracing.md, "Against OpenImageIO's resize"). Same filter as renderer/upsampling's
// upsample_reference: Lanczos-3 over six input pixels, normalised weights, edges clamped.
#include "core/image.h"

namespace fovlab::bench {

// `image` enlarged by `factor` per axis with ImageBufAlgo::resize("lanczos3"), on every core.
// The filter width is left to OpenImageIO: it measures widths in output pixels and, when
// enlarging, defaults to 6 x factor of them, six input pixels. (An explicit width of 6 would
// squeeze the kernel into three input pixels: another filter, which aliases; on a ramp its outputs
// 2i and 2i + 1 come out in the wrong order.) Throws InputError with OpenImageIO's message on failure.
Image resize_with_openimageio(const Image& image, int factor);

}  // namespace fovlab::bench

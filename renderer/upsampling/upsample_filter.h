#pragma once
// Upsampling of the emulated foveated path tracer's zone buffers (Polychronakis et al. 2021 section 3.1): a buffer
// of 1/4 or 1/16 the pixel count, made by nearest-neighbour decimation, is brought back to full
// size by an integer factor per axis. This file holds the filters and the double-precision CPU
// reference; renderer/upsampling/upsampler.h runs the same filter on the GPU. Definitions in
// docs/foveated-path-tracing.md ("Upsampling").
//
// Sampling: output pixel x (centre x + 0.5) reads the input at u = (x + 0.5) / factor - 0.5 (in
// input pixel centres), so the output covers exactly the input's extent. Taps outside the input
// repeat its edge pixel (clamp). Weights are normalised to sum to 1 per output pixel and axis.
// Lanczos-3 rings: values are not clamped, so an output may leave the input's range by the
// filter's overshoot (on a 1-D step, 10.3 % of its height at factor 2 and 11.8 % at factor 4, on
// either side); linear-light EXR keeps it.
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"

namespace fovlab {

enum class UpsampleFilter { lanczos3, bilinear, nearest };

const char* upsample_filter_name(UpsampleFilter filter);  // "lanczos3", "bilinear", "nearest"
std::optional<UpsampleFilter> parse_upsample_filter(const std::string& name);

// The 1-D kernel: Lanczos-3 L(t) = sinc(t) sinc(t / 3) for |t| < 3, else 0 (sinc(t) = sin(pi t) /
// (pi t), 1 at 0); bilinear max(0, 1 - |t|); nearest 1 for -0.5 <= t < 0.5.
double upsample_kernel(UpsampleFilter filter, double t);

// The normalised weights the GPU passes use, computed in double, by input cell: the outputs
// c * factor + r (phase r = 0 .. factor - 1) of input pixel c all read their taps from the
// kUpsampleCellTaps input pixels c - 3 .. c + 3. For each phase, kUpsampleCellTaps weights for those
// pixels, 0 where the phase's kernel does not reach (Lanczos-3 reaches six of them, bilinear and
// nearest two). factor * kUpsampleCellTaps values.
constexpr int kUpsampleCellTaps = 7;
std::vector<float> upsample_cell_weights(UpsampleFilter filter, int factor);

// Upsamples every channel of `image` by `factor` (1 to 8) along each axis, in double precision.
Image upsample_reference(const Image& image, int factor, UpsampleFilter filter);

}  // namespace fovlab

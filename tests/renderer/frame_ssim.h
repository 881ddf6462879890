#pragma once
// SSIM of two traced frames as they are shown: both sRGB-encoded, as fovlab bench compares them.
#include "core/colour.h"
#include "metrics/image_metrics.h"
#include "renderer/sphere_tracing/sphere_tracer.h"

namespace fovlab::test {

inline double srgb_ssim(const SphereTraceResult& reference, const SphereTraceResult& test) {
  return metrics::ssim(encode_srgb(reference.colour_linear), encode_srgb(test.colour_linear)).mean_ssim;
}

}  // namespace fovlab::test

#pragma once
// FIPR's foveation mask (Polychronakis et al. 2023 section 3.2.3), the CPU reference of the mask pass
// (renderer/shaders/foveation_mask.comp.glsl): which full-resolution pixels are traced at the top
// level of the pyramid this frame. A pixel is traced when its threshold xi (a hash of seed, frame
// and pixel) is below its probability P, built from the acuity model (foveation/
// acuity_model.h) and the Sobel edge map of the low-resolution depth. Definitions and the choice of
// reading: docs/foveation.md ("Foveation mask").
#include <cstdint>
#include <optional>
#include <string>

#include "core/render_choices.h"
#include "foveation/acuity_model.h"

namespace fovlab {

// How acuity probability and edges combine: MaskCombine (core/render_choices.h).
const char* mask_combine_name(MaskCombine combine);  // "max", "fovea-or-product", "product", "acuity"
std::optional<MaskCombine> parse_mask_combine(const std::string& name);

// P for a pixel from its acuity probability (in [0, 1], 1 in the fovea) and its edge flag.
double mask_probability(MaskCombine combine, double acuity_probability, bool in_fovea, bool edge);

// The pixel's threshold xi in [0, 1): the top 24 bits of a 32-bit hash of (seed, frame, x, y),
// exactly representable in float, so the GPU and this code agree bit for bit. The hash is
// Wellons' "lowbias32" integer mixer applied in a chain (docs/foveation.md).
uint32_t mask_hash(uint32_t seed, uint32_t frame, uint32_t x, uint32_t y);
double mask_threshold(uint32_t seed, uint32_t frame, uint32_t x, uint32_t y);

}  // namespace fovlab

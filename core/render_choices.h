#pragma once
// The named choices of the rendering methods, defined once: the study's typed parameters
// (study/stimulus/method_parameters.h), foveation/ and the renderer all use these enums, so a
// stimulus's choice reaches the renderer as it is, never cast from a mirror by order. A choice's
// value is the index of its name in the method's descriptor (study/stimulus/render_method.cpp), so
// the enumerators' order is that of the names the configs and logs carry.
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <optional>
#include <string_view>

namespace fovlab {

// How FIPR's foveation mask combines the acuity probability and the depth edges (Polychronakis et
// al. 2023, section 3.2.3; docs/foveation.md). The paper multiplies them, yet its Fig. 6 keeps the
// whole fovea; `max` is the reading that matches the figure and is the default.
// Names: "max", "fovea-or-product", "product", "acuity".
enum class MaskCombine : uint32_t {
  max = 0,               // P = max(P_acuity, edge): the fovea in full, every peripheral edge, the rest by acuity
  fovea_or_product = 1,  // P = 1 in the fovea, else P_acuity x edge (peripheral non-edges never)
  product = 2,           // P = P_acuity x edge: the paper's words taken literally (drops fovea non-edges)
  acuity = 3,            // P = P_acuity: edges ignored (the usual foveated renderer)
};

// How a pyramid level below the top decides where its rays stop (IPR and FIPR; docs/scenes.md
// "Inverted pyramid"). Names: "ray", "cone".
enum class CoarseTest : uint32_t {
  centre_ray = 0,  // the paper's: the ray through the level pixel's centre hits within the level's threshold;
                   // thin geometry between two centre rays can be stepped over and lost to the finer levels
  cone = 1,        // conservative: the level pixel's whole cone (corners and the top level's hit band) stops
                   // where geometry may enter it, so no finer ray starts behind a surface it would hit
};

// How FIPR fills a pixel outside the mask from the mid level (periphery_steps 0; docs/foveation.md).
// The mid colours are interpolated at the frame's pixels, so each stands for the frame's pixel at its
// position; a texture filtered over the mid pixel's own 2-pixel footprint is blurred twice.
// Names: "mid-footprint-bilinear", "bilinear", "catmull-rom".
enum class PeripheryReconstruction : uint32_t {
  mid_footprint_bilinear = 0,  // as built first (every log before schema 5): textured over the mid pixel's
                               // footprint, interpolated bilinearly
  bilinear = 1,                // textured over one frame pixel's footprint, interpolated bilinearly
  catmull_rom = 2,             // textured so, interpolated by Catmull-Rom over 4x4 mid pixels (bilinear
                               // where a tap is stale): sharper on filtered textures, and on aliased detail
};
inline constexpr PeripheryReconstruction kPeripheryReconstructions[] = {PeripheryReconstruction::mid_footprint_bilinear,
                                                                        PeripheryReconstruction::bilinear,
                                                                        PeripheryReconstruction::catmull_rom};

// What FIPR does where a coarse ray (low or mid level, the paper's centre-ray test) passed a surface
// within its pixel's cone without hitting it: a wire between two rays, a silhouette it grazed.
// Names: "ignore", "promote".
enum class NearMisses : uint32_t {
  ignore = 0,   // the paper's (every log before schema 6): the periphery takes the colour behind it
  promote = 1,  // the mid level's unmasked children of such a pixel are traced and shaded in full at the
                // top level, from in front of it; nothing else changes (docs/foveation.md, "Near misses")
};
inline constexpr NearMisses kNearMisses[] = {NearMisses::ignore, NearMisses::promote};

// Which depth of FIPR's low level its Sobel edges are found in (docs/foveation.md, "Edges under the
// cone"). With coarse_test ray both are the centre ray's depth. Names: "level", "centre-ray".
enum class EdgeDepth : uint32_t {
  level = 0,       // the depth the low level passes on; with the cone, where its cone stopped, up to 1.5 cone
                   // radii in front of what may enter it (every FIPR stimulus of logs before schema 10)
  centre_ray = 1,  // the depth where the ray through the low pixel's centre hits (with the cone: marched on
                   // from where the cone stopped), the paper's pyramid's; the depth passed on stays the cone's
};
inline constexpr EdgeDepth kEdgeDepths[] = {EdgeDepth::level, EdgeDepth::centre_ray};

// How the sampling models' pass 2 reads the reduced buffers (RMFR, KFR, the hyperbolic layers; Ye et
// al. 2022) at a pixel's forward-mapped position: bilinear (2x2 samples, the paper's), or Lanczos-2
// (4x4 samples, sinc(x) sinc(x/2) per axis, the weights of the shaded samples normalised), sharper
// but with ringing. The linear model is filled by pull-push either way. Names: "bilinear", "lanczos".
enum class ResampleFilter : uint32_t { bilinear = 0, lanczos2 = 1 };

// Ye et al. 2022's sampling models: where a frame's samples fall around the gaze (the maps are
// foveation/sampling_map.h's). A model is one entry here and its name below; the study's methods
// pair it with each source of samples (study/stimulus/method_parameters.h: "rmfr" on the sphere
// tracer, "pt-rmfr" on path-traced frames), bench measures it under its name, and the GPU's MODEL_*
// constant (renderer/shaders/shared/sampling_params.h) is checked against it.
enum class SamplingModel : uint32_t {
  rectangular = 0,       // RMFR (Ye et al. 2022, section 3)
  hyperbolic = 1,        // three layers of falling resolution (Guenter et al.)
  linear = 2,            // linear fall-off of the sampling probability (Weier et al.)
  kernel_log_polar = 3,  // KFR (Meng et al.)
};
// Each model's name, in the enum's order.
inline constexpr const char* kSamplingModelNames[] = {"rmfr", "hyperbolic", "linear", "kfr"};
inline constexpr size_t kSamplingModelCount = std::size(kSamplingModelNames);

inline const char* sampling_model_name(SamplingModel model) {
  const auto index = static_cast<size_t>(model);
  return index < kSamplingModelCount ? kSamplingModelNames[index] : "?";
}
inline std::optional<SamplingModel> parse_sampling_model(std::string_view name) {
  for (size_t index = 0; index < kSamplingModelCount; ++index)
    if (name == kSamplingModelNames[index]) return static_cast<SamplingModel>(index);
  return std::nullopt;
}

}  // namespace fovlab

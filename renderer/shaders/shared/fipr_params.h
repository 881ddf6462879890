#ifndef FOVLAB_FIPR_PARAMS_H
#define FOVLAB_FIPR_PARAMS_H
// The push constants of FIPR's passes around the sphere tracer (Polychronakis et al. 2023) and the
// words of its lists; SphereTracer fills them (renderer/sphere_tracing/).
#include "gpu_types.h"

FOVLAB_GPU_BEGIN

// min_filter.comp.glsl
struct MinFilterParams {
  uvec2 size;  // pixels of the level
  int radius;  // 0 (filter size 1), 1 (3x3), 2 (5x5)
};

// depth_edges.comp.glsl
struct EdgeParams {
  uvec2 size;                // pixels of the low-resolution level
  float relative_threshold;  // edge when |Sobel(depth)| > relative_threshold * depth
};

// foveation_mask.comp.glsl
const uint FLAG_TRACE_ALL = 1u;     // no usable gaze: every pixel is traced in full
const uint FLAG_ALL_DUE = 2u;       // no history yet: every unmasked pixel is due for a refresh
const uint FLAG_LIST_REFRESH = 4u;  // the periphery is traced: list the unmasked pixels due
                                    // (COUNTER_REFRESH_LIST_PIXELS, sphere_trace_params.h)

struct MaskParams {
  uvec2 frame_size;  // full-resolution pixels
  uvec2 mid_size;    // mid-level pixels
  uvec2 low_size;    // low-level pixels (the edge map)
  uint low_scale;    // full-resolution pixels per low-level pixel along each axis
  uint combine;      // COMBINE_* (MaskCombine)
  vec2 gaze_px;      // in full-resolution pixels (finite, clamped by the renderer)
  vec2 pixel_pitch_mm;
  vec2 principal_point_px;  // where the eye's perpendicular meets the frame (eccentricity.glsl)
  float viewing_distance_mm;
  float fovea_radius_deg;
  float outer_periphery_radius_deg;  // a huge value when there is none
  uint seed;
  uint frame_index;
  uint flags;  // FLAG_TRACE_ALL, FLAG_ALL_DUE, FLAG_LIST_REFRESH
  uint refresh_period;
};

// Per mid pixel (mid_flags): masked children (bits 0-3) | children (bits 4-7) | due for a refresh (bit 8).
const uint MID_FLAG_DUE = 256u;

// fipr_mid_list.comp.glsl
struct MidListParams {
  uvec2 mid_size;         // pixels of the mid level
  uvec2 start_size;       // pixels of the level below (its filtered depth)
  int min_filter_radius;  // the top level starts from the minimum over this radius
  uint list_counter;      // counters[list_counter]: the list's length
};

// An entry of the mid level's list (fipr_mid_list.comp.glsl writes it, sphere_trace.comp.glsl reads
// it): the mid pixel's index, its unmasked children (0-4) and whether they are due for a refresh.
const uint fovlab_mid_entry_index_mask = 0x0FFFFFFFu;
const uint fovlab_mid_entry_unmasked_shift = 28u;
const uint fovlab_mid_entry_refresh = 0x80000000u;

// fipr_reconstruct.comp.glsl
struct FiprReconstructParams {
  uvec2 frame_size;
  uvec2 mid_size;
  uint refresh_period;
  uint frame_index;
  uint catmull_rom;  // 1: PeripheryReconstruction::catmull_rom
};

// masked_blur.comp.glsl
struct BlurParams {
  uvec2 size;
};

// MaskParams::combine: core/render_choices.h's MaskCombine.
const uint COMBINE_MAX = 0u;
const uint COMBINE_FOVEA_OR_PRODUCT = 1u;
const uint COMBINE_PRODUCT = 2u;
const uint COMBINE_ACUITY = 3u;

FOVLAB_GPU_END

#ifdef __cplusplus
#include "core/render_choices.h"
static_assert(fovlab::gpu::COMBINE_MAX == uint32_t(fovlab::MaskCombine::max) &&
              fovlab::gpu::COMBINE_FOVEA_OR_PRODUCT == uint32_t(fovlab::MaskCombine::fovea_or_product) &&
              fovlab::gpu::COMBINE_PRODUCT == uint32_t(fovlab::MaskCombine::product) &&
              fovlab::gpu::COMBINE_ACUITY == uint32_t(fovlab::MaskCombine::acuity));
#endif

#endif

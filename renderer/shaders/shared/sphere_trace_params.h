#ifndef FOVLAB_SPHERE_TRACE_PARAMS_H
#define FOVLAB_SPHERE_TRACE_PARAMS_H
// sphere_trace.comp.glsl's push constants and flags, and the indices of its counters; SphereTracer
// fills them (renderer/sphere_tracing/).
#include "gpu_types.h"

FOVLAB_GPU_BEGIN

const uint FLAG_SHADE = 1u;               // top level: shade and write colour
const uint FLAG_HAS_START = 2u;           // start rays at start_depth of the parent pixel
const uint FLAG_FOVEATED_MID = 4u;        // FIPR mid level
const uint FLAG_FOVEATED_TOP = 8u;        // FIPR top level: the periphery's refresh list in mask_values
const uint FLAG_CONE = 16u;               // depth levels (and FIPR's mid level) march their pixel's cone
const uint FLAG_MASKED_LIST = 32u;        // FIPR top level: the masked pixels listed in mask_values
const uint FLAG_SAMPLE_LIST = 64u;        // sampling models: the samples listed in mask_values, four words each
                                          // (x, y and footprint in pixels as float bits, then the sample's entry);
                                          // colour (alpha 1: shaded) and steps go to that entry
const uint FLAG_START_SAME_SIZE = 128u;   // the start buffer is this level's own size (pixel -> pixel)
const uint FLAG_NEAR_MISS = 256u;         // FIPR: where a depth level's ray passed a surface within its cone
                                          // (near_depth); the mid level promotes the children of such a pixel
const uint FLAG_SAMPLE_DEPTH_OUT = 512u;  // GT before its one-step floor: each sample's stop to level_depth
const uint FLAG_SAMPLE_DEPTH_IN = 1024u;  // the one-step floor: each sample starts at its entry of start_depth

struct TraceParams {
  uvec2 level_size;        // pixels of this level
  uvec2 start_size;        // pixels of the start-depth buffer (the level below); unused without FLAG_HAS_START
  vec2 frame_size;         // pixels of the full-resolution frame
  float time_s;            // scene time
  float hit_threshold;     // a ray hits when distance < t * pixel_angle_rad * level_scale * hit_threshold
  uint samples_per_pixel;  // 1, 4 or 16 (top level; FIPR's mid level: 4 for a one-pixel texture footprint)
  uint max_steps;          // step cap of one ray at this level
  uint level_scale;        // full-resolution pixels per level pixel along each axis (1, 2, 4, ...)
  uint flags;              // FLAG_*
  uint frame_index;        // FIPR: frame of the sequence (stamps the mid level's colours)
  uint periphery_steps;    // FIPR: 0: the mid level shades the pixels its unmasked children take
                           // (fipr_reconstruct); else those are traced from the mid depth with this
                           // step budget and shaded (1 sample)
};

// The sphere tracer's counters buffer (COUNTER_COUNT words, zeroed before a frame): the index of each
// count. The passes around the tracer add to them too: foveation_mask.comp.glsl lists the masked
// pixels and the periphery's refresh list, fipr_mid_list.comp.glsl the mid level's list, and
// sampling_positions.comp.glsl the sampling models' samples (in COUNTER_MASKED_PIXELS).
const uint COUNTER_CAPPED_RAYS = 0u;          // rays stopped by their step cap
const uint COUNTER_RESTARTED_RAYS = 1u;       // IPR rays whose start depth was inside geometry
const uint COUNTER_MASKED_PIXELS = 2u;        // the masked pixels' list (or the listed samples)
const uint COUNTER_MID_TRACED_PIXELS = 3u;    // FIPR's mid level: its pixels traced
const uint COUNTER_MID_SHADED_PIXELS = 4u;    // and shaded
const uint COUNTER_REFRESHED_PIXELS = 5u;     // unmasked pixels given a new colour this frame
const uint COUNTER_REFRESH_LIST_PIXELS = 6u;  // the periphery's refresh list, when the periphery is traced
const uint COUNTER_MID_LIST_PIXELS = 7u;      // the mid level's list
const uint COUNTER_COUNT = 8u;                // words of the buffer

FOVLAB_GPU_END

#endif

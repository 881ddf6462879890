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
const uint FLAG_EDGE_DEPTH = 2048u;       // FIPR's low level under the cone: its centre ray's depth to edge_depth

struct TraceParams {
  uvec2 level_size;        // pixels of this level
  uvec2 start_size;        // pixels of the start-depth buffer (the level below); unused without FLAG_HAS_START
  vec2 frame_size;         // pixels of the full-resolution frame
  float time_s;            // scene time
  float hit_threshold;     // a ray hits when distance < t * pixel_angle_rad * level_scale * hit_threshold
  uint samples_per_pixel;  // 1, 4 or 16 (top level; FIPR's mid level: 4 for a one-pixel texture footprint)
  uint max_steps;          // step cap of one ray at this level
  uint level_scale;        // full-resolution pixels per level pixel along each axis (1, 2, 4, ...)
  uint flags;              // FLAG_*: which pipeline runs the pass (the shader reads them as its
                           // specialization constant, fovlab_trace_flags, not from here)
  uint frame_index;        // FIPR: frame of the sequence (stamps the mid level's colours)
  uint periphery_steps;    // FIPR: 0: the mid level shades the pixels its unmasked children take
                           // (fipr_reconstruct); else those are traced from the mid depth with this
                           // step budget and shaded (1 sample)
  // A headset eye's view (renderer/scene/eye_view.h), when eye_view is 1: the camera ray from the
  // eye's four tan-angles (left, right, up, down) and the eye at eye_position in the head's frame
  // (the scene's camera; x right, y up, z backwards), turned by the quaternion eye_orientation.
  // 0: the scene camera's symmetric frustum.
  vec4 eye_tan_angles;
  vec4 eye_orientation;
  vec3 eye_position;
  uint eye_view;
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
// The step breakdown of the top level's shaded samples (SphereTraceSettings::step_breakdown): counted
// only by the tracer's step-breakdown variant (sphere_trace.comp.glsl compiled with
// FOVLAB_STEP_BREAKDOWN defined); the plain tracer leaves these words 0. A 64-bit count is two
// words, low then high. docs/benchmarks.md "Where the steps go (issue 41)" defines the categories.
const uint COUNTER_STEP_CATEGORY_STEPS = 8u;         // STEP_CATEGORY_COUNT 64-bit counts: steps per category
const uint COUNTER_STEP_CATEGORY_SAMPLES = 22u;      // STEP_CATEGORY_COUNT words: samples with a step in it
const uint COUNTER_STEP_HISTOGRAM = 29u;             // STEP_HISTOGRAM_BINS words: samples by their steps
const uint COUNTER_STEP_ONE_SURFACE_PIXELS = 37u;    // pixels whose samples all hit one surface at one depth
const uint COUNTER_STEP_ONE_SURFACE_STEPS = 38u;     // 64-bit: all steps of those pixels' samples
const uint COUNTER_STEP_ONE_SURFACE_APPROACH = 40u;  // 64-bit: their samples' approach steps
const uint COUNTER_STEP_ONE_SURFACE_LONGEST = 42u;   // 64-bit: each such pixel's longest approach, summed
const uint COUNTER_COUNT = 44u;                      // words of the buffer

// The step breakdown's categories: every step of a shaded sample's march is in one. A step is near
// a surface when its distance bound is under STEP_NEAR_FOOTPRINTS pixel footprints at its depth (or
// under the hit threshold, if that is larger).
const uint STEP_CATEGORY_APPROACH = 0u;    // a hit: the steps before its first near step
const uint STEP_CATEGORY_SILHOUETTE = 1u;  // a hit: from its first near step to its final near run
                                           // (near surfaces it passed, and the free space after them)
const uint STEP_CATEGORY_GRAZING = 2u;     // a hit: its final near run, when at least STEP_LONG_RUN steps
                                           // and the surface under STEP_GRAZING_SINE to the ray
const uint STEP_CATEGORY_SLOW_BOUND = 3u;  // a hit: such a long final near run on a surface facing the ray
                                           // more steeply (the scene's distance bound under-estimates)
const uint STEP_CATEGORY_FINAL = 4u;       // a hit: its final near run when shorter, and the refining step
const uint STEP_CATEGORY_MISS = 5u;        // every step of a sample that leaves the bounds (the background)
const uint STEP_CATEGORY_OTHER = 6u;       // a sample stopped by the step cap; a start inside geometry
const uint STEP_CATEGORY_COUNT = 7u;
const uint STEP_HISTOGRAM_BINS = 8u;  // a sample's steps: 0-1, 2, 3-4, 5-8, 9-16, 17-32, 33-64, 65 or more
const float STEP_NEAR_FOOTPRINTS = 1.0;
const uint STEP_LONG_RUN = 4u;              // (an exact distance to a plane takes that many under about 22 degrees)
const float STEP_GRAZING_SINE = 0.375;      // sine of 22 degrees: |normal . direction| at the hit below it
const float STEP_ONE_SURFACE_DEPTH = 0.05;  // a one-surface pixel's samples lie within 5 % of the nearest's depth

FOVLAB_GPU_END

#endif

#ifndef FOVLAB_ZONE_BLEND_PARAMS_H
#define FOVLAB_ZONE_BLEND_PARAMS_H
// The zone blend's push constants (zone_weights.glsl, zone_blend, zone_display, zone_band and
// buffer_copy.comp.glsl); ZoneBlender fills them (renderer/zone_blend/). foveation/zone_layout.cpp
// is the reference.
#include "gpu_types.h"

FOVLAB_GPU_BEGIN

struct BlendParams {
  // Squared tangents of the band edges (radius -/+ band / 2): foveal inner, foveal outer, middle
  // inner, middle outer; -1 below 0 degrees, a huge value from 90 degrees. Outside the bands the
  // zone follows from tan^2 of the eccentricity, |g x p|^2 / (g . p)^2 for the unit ray g to the
  // gaze and the ray p to the pixel, without an arctangent.
  vec4 edge_tan2;
  // In the eye's millimetres (foveation/display_geometry.h): g, made on the CPU in double,
  // so that a gaze far off the screen stays exact; pixel (x, y)'s centre at
  // (first_pixel_mm + (x, y) * pixel_pitch_mm, viewing_distance_mm).
  vec3 gaze_direction;
  float viewing_distance_mm;
  vec2 first_pixel_mm;
  vec2 pixel_pitch_mm;
  uvec2 frame_size;
  // Inside a band the weight of the inner zone is clamp((band_end - e) / band, 0, 1) for the
  // eccentricity e in degrees: band_end = radius + band / 2 of the foveal and the middle boundary.
  vec2 band_end_deg;
  float band_per_deg;  // 1 / band (bands of 0 degrees have no pixels inside)
  uint has_middle;     // 0: no middle zone (its radius is not beyond the fovea's)
};

// buffer_copy.comp.glsl
struct CopyParams {
  uvec2 frame_size;
};

FOVLAB_GPU_END

#endif

#version 460
// FIPR pass 3 (Polychronakis et al. 2023 section 3.2.3): the binary foveation mask. One invocation per pixel of the
// mid level; it decides its 2x2 full-resolution children. For each child: exact eccentricity from
// the gaze (the angle at the eye, as foveation/display_geometry.cpp), the acuity
// probability (acuity_model.cpp), combined with the upscaled edge flag (foveation_mask.cpp), then
// traced at the top level when the pixel's hashed threshold is below that probability. The CPU code
// is the reference; tests compare the two pixel by pixel. Masked pixels are also appended to a list
// (in no fixed order; each pixel's result does not depend on it), so the top level traces them
// densely instead of leaving most SIMD lanes idle on a sparse mask.
#extension GL_GOOGLE_include_directive : require
#include "eccentricity.glsl"
#include "lowbias32.glsl"
#include "shared/fipr_params.h"
#include "shared/sphere_trace_params.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Edges { uint edges[]; };       // low level, 0 or 1
layout(std430, binding = 1) writeonly buffer Mask { uint mask[]; };        // full resolution, 0 or 1
// Per mid pixel: masked children (bits 0-3) | children (bits 4-7) | due for a refresh (bit 8).
layout(std430, binding = 2) writeonly buffer MidFlags { uint mid_flags[]; };
layout(std430, binding = 3) buffer Counters { uint counters[]; };          // the sphere tracer's (COUNTER_*)
layout(std430, binding = 4) writeonly buffer MaskedList { uint masked_list[]; };  // their pixel indices
layout(std430, binding = 5) writeonly buffer RefreshList { uint refresh_list[]; };  // unmasked pixels due now

layout(push_constant) uniform MaskParamsBlock { MaskParams params; };

// Whether the unmasked pixels under a mid pixel get a new colour this frame (the mid and
// reconstruction passes read it from the mid flags). Periods are staggered over tiles of 16x16
// full-resolution pixels (8x8 mid pixels): period 2 in a checkerboard of tiles, period 4 in 2x2
// blocks of tiles, so each frame refreshes an even spread of 1/2 or 1/4 of the periphery, and a tile
// is one workgroup of the mid level, whose pixels then skip or trace together (docs/foveation.md).
bool refresh_due(uvec2 mid_pixel) {
  if ((params.flags & FLAG_ALL_DUE) != 0u || params.refresh_period <= 1u) return true;
  uvec2 tile = mid_pixel / 8u;
  uint phase = params.refresh_period == 2u ? ((tile.x + tile.y) & 1u) : ((tile.x & 1u) | ((tile.y & 1u) << 1));
  return phase == params.frame_index % params.refresh_period;
}

float mask_threshold(uvec2 pixel) { return pixel_threshold(params.seed, params.frame_index, pixel); }

float eccentricity_deg(vec2 point_px) {
  vec3 gaze_ray =
      ray_from_eye(params.gaze_px, params.principal_point_px, params.pixel_pitch_mm, params.viewing_distance_mm);
  return eccentricity_between_deg(gaze_ray, ray_from_eye(point_px, params.principal_point_px, params.pixel_pitch_mm,
                                                         params.viewing_distance_mm));
}

float acuity_probability(float eccentricity) {
  if (!(eccentricity > params.fovea_radius_deg)) return 1.0;
  if (eccentricity > params.outer_periphery_radius_deg) return 0.0;
  return 0.90964 * exp(-eccentricity / 2.9661) + 0.00792;
}

float combined_probability(float acuity, bool in_fovea, bool edge) {
  float edge_value = edge ? 1.0 : 0.0;
  if (params.combine == COMBINE_MAX) return max(acuity, edge_value);
  if (params.combine == COMBINE_FOVEA_OR_PRODUCT) return in_fovea ? 1.0 : acuity * edge_value;
  if (params.combine == COMBINE_PRODUCT) return acuity * edge_value;
  return acuity;
}

void main() {
  uvec2 mid = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(mid, params.mid_size))) return;
  uint masked = 0u;
  uint children = 0u;
  uint masked_indices[4];
  uint due = 0u;
  uint due_indices[4];
  bool due_now = refresh_due(mid);
  bool list_due = (params.flags & FLAG_LIST_REFRESH) != 0u && due_now;
  for (uint j = 0u; j < 2u; ++j) {
    for (uint i = 0u; i < 2u; ++i) {
      uvec2 pixel = mid * 2u + uvec2(i, j);
      if (any(greaterThanEqual(pixel, params.frame_size))) continue;
      children += 1u;
      bool traced = true;
      if ((params.flags & FLAG_TRACE_ALL) == 0u) {
        float eccentricity = eccentricity_deg(vec2(pixel) + 0.5);
        uvec2 low = min(pixel / params.low_scale, params.low_size - 1u);
        bool edge = edges[low.y * params.low_size.x + low.x] != 0u;
        bool in_fovea = !(eccentricity > params.fovea_radius_deg);
        float probability = combined_probability(acuity_probability(eccentricity), in_fovea, edge);
        traced = mask_threshold(pixel) < probability;
      }
      uint pixel_index = pixel.y * params.frame_size.x + pixel.x;
      mask[pixel_index] = traced ? 1u : 0u;
      if (traced) {
        masked_indices[masked++] = pixel_index;
      } else if (list_due) {
        due_indices[due++] = pixel_index;
      }
    }
  }
  mid_flags[mid.y * params.mid_size.x + mid.x] = masked | (children << 4) | (due_now ? MID_FLAG_DUE : 0u);
  if (masked > 0u) {
    uint first = atomicAdd(counters[COUNTER_MASKED_PIXELS], masked);
    for (uint i = 0u; i < masked; ++i) masked_list[first + i] = masked_indices[i];
  }
  if (due > 0u) {
    uint first = atomicAdd(counters[COUNTER_REFRESH_LIST_PIXELS], due);
    for (uint i = 0u; i < due; ++i) refresh_list[first + i] = due_indices[i];
  }
}

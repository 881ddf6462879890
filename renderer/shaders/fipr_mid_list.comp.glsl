#version 460
// FIPR's mid level from a compacted list (docs/foveation.md, "Passes"). One invocation per mid-level
// pixel decides whether its ray is traced: the top level needs its depth (a masked pixel within the
// min filter's radius: the top level starts from the filtered mid depth) or its unmasked children
// are due for a refresh (the mid level shades them, or the top level traces them from its depth).
// Those pixels are appended to a list that the trace pass (sphere_trace.comp.glsl,
// FLAG_FOVEATED_MID) runs over densely, 64 entries a workgroup, instead of paying a SIMD lane for
// every pixel of the level; each entry carries what the trace needs (fovlab_mid_entry_* in
// shared/fipr_params.h). The other pixels pass their parent's (filtered) depth on here, with no steps. The list's
// order is that of the atomics; no pixel's result depends on it.
#extension GL_GOOGLE_include_directive : require
#include "shared/fipr_params.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

// Per mid pixel: masked children (bits 0-3) | children (bits 4-7) | due for a refresh (bit 8).
layout(std430, binding = 0) readonly buffer MidFlags { uint mid_flags[]; };
layout(std430, binding = 1) readonly buffer StartDepth { float start_depth[]; };
layout(std430, binding = 2) writeonly buffer LevelDepth { float level_depth[]; };
layout(std430, binding = 3) writeonly buffer LevelSteps { uint level_steps[]; };
layout(std430, binding = 4) buffer Counters { uint counters[]; };
layout(std430, binding = 5) writeonly buffer MidList { uint mid_list[]; };

layout(push_constant) uniform MidListParamsBlock { MidListParams params; };

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, params.mid_size))) return;
  uint index = pixel.y * params.mid_size.x + pixel.x;
  bool need_depth = false;
  int radius = params.min_filter_radius;
  for (int dy = -radius; dy <= radius; ++dy) {
    for (int dx = -radius; dx <= radius; ++dx) {
      uvec2 neighbour = uvec2(clamp(ivec2(pixel) + ivec2(dx, dy), ivec2(0), ivec2(params.mid_size) - 1));
      need_depth = need_depth || (mid_flags[neighbour.y * params.mid_size.x + neighbour.x] & 15u) != 0u;
    }
  }
  uint flags_here = mid_flags[index];
  uint unmasked_children = ((flags_here >> 4) & 15u) - (flags_here & 15u);
  bool refresh_children = unmasked_children > 0u && (flags_here & MID_FLAG_DUE) != 0u;
  if (need_depth || refresh_children) {
    uint slot = atomicAdd(counters[params.list_counter], 1u);
    mid_list[slot] = index | (unmasked_children << fovlab_mid_entry_unmasked_shift) | (refresh_children ? fovlab_mid_entry_refresh : 0u);
    return;
  }
  uvec2 parent = min(pixel / 2u, params.start_size - 1u);
  level_depth[index] = start_depth[parent.y * params.start_size.x + parent.x];  // in front of every surface the parent saw
  level_steps[index] = 0u;
}

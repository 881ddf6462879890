#version 460
// A plain copy of one float RGBA buffer into another, one invocation a texel in rows of 64 as
// zone_blend.comp.glsl runs: the least a blend of full-size buffers must do (read every pixel once,
// write it once), and so the baseline its cost is measured against (bench/blend_cost.h).
#extension GL_GOOGLE_include_directive : require
#include "shared/zone_blend_params.h"
layout(local_size_x = ROW_GROUP_WIDTH, local_size_y = 1, local_size_z = 1) in;


layout(std430, binding = 0) readonly buffer Source { vec4 source[]; };
layout(std430, binding = 1) writeonly buffer Target { vec4 target[]; };

layout(push_constant) uniform CopyParamsBlock { CopyParams params; };

void main() {
  uvec2 pixel = uvec2(gl_GlobalInvocationID.x, gl_GlobalInvocationID.y);
  if (pixel.x >= params.frame_size.x) return;
  uint index = pixel.y * params.frame_size.x + pixel.x;
  target[index] = source[index];
}

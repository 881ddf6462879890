#version 460
// Neighbourhood minimum of a depth level (inverted pyramid, Polychronakis et al. 2023 section 3.2.4): each output
// pixel holds the smallest depth among the (2 * radius + 1)^2 input pixels around it, clamped at the
// borders. The next level starts its rays at this depth, so a ray next to a nearer surface starts
// in front of it instead of behind it.
#extension GL_GOOGLE_include_directive : require
#include "shared/fipr_params.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer InputDepth { float input_depth[]; };
layout(std430, binding = 1) writeonly buffer FilteredDepth { float filtered_depth[]; };

layout(push_constant) uniform MinFilterParamsBlock { MinFilterParams params; };

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(params.size);
  if (any(greaterThanEqual(pixel, size))) return;
  float smallest = 3.402823e38;
  for (int dy = -params.radius; dy <= params.radius; ++dy) {
    for (int dx = -params.radius; dx <= params.radius; ++dx) {
      ivec2 neighbour = clamp(pixel + ivec2(dx, dy), ivec2(0), size - 1);
      smallest = min(smallest, input_depth[neighbour.y * size.x + neighbour.x]);
    }
  }
  filtered_depth[pixel.y * size.x + pixel.x] = smallest;
}

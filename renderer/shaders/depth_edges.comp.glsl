#version 460
// FIPR pass 2 (Polychronakis et al. 2023 section 3.2.2): Sobel edges of the low-resolution depth. A pixel is an edge
// (1) when the Sobel gradient magnitude of the depth, relative to the pixel's own depth, exceeds
// relative_threshold; else 0. Relative, so the same threshold serves near and far geometry: a depth
// step of s * depth between neighbours gives a magnitude of about 4 s (docs/foveation.md).
#extension GL_GOOGLE_include_directive : require
#include "shared/fipr_params.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer LowDepth { float low_depth[]; };
layout(std430, binding = 1) writeonly buffer Edges { uint edges[]; };

layout(push_constant) uniform EdgeParamsBlock { EdgeParams params; };

float depth_at(ivec2 pixel) {
  ivec2 clamped = clamp(pixel, ivec2(0), ivec2(params.size) - 1);
  return low_depth[clamped.y * int(params.size.x) + clamped.x];
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, ivec2(params.size)))) return;
  float d[3][3];
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) d[dy + 1][dx + 1] = depth_at(pixel + ivec2(dx, dy));
  float gx = (d[0][2] + 2.0 * d[1][2] + d[2][2]) - (d[0][0] + 2.0 * d[1][0] + d[2][0]);
  float gy = (d[2][0] + 2.0 * d[2][1] + d[2][2]) - (d[0][0] + 2.0 * d[0][1] + d[0][2]);
  float magnitude = sqrt(gx * gx + gy * gy);
  edges[pixel.y * int(params.size.x) + pixel.x] = magnitude > params.relative_threshold * max(d[1][1], 1e-6) ? 1u : 0u;
}

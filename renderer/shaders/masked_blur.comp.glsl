#version 460
// FIPR pass 5 (Polychronakis et al. 2023 section 3.2.5): Gaussian blur guided by the foveation mask. Pixels rendered
// at the top level keep their value; a pixel filled from the mid level is blurred (5x5 Gaussian,
// sigma 1 pixel, weights normalised at the frame's borders) when a top-level pixel lies within its
// 5x5 window, i.e. in the transition between high- and low-fidelity pixels. Elsewhere it is copied.
#extension GL_GOOGLE_include_directive : require
#include "shared/fipr_params.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Colour { vec4 colour[]; };
layout(std430, binding = 1) readonly buffer Mask { uint mask[]; };
layout(std430, binding = 2) writeonly buffer Blurred { vec4 blurred[]; };

layout(push_constant) uniform BlurParamsBlock { BlurParams params; };

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(params.size);
  if (any(greaterThanEqual(pixel, size))) return;
  int index = pixel.y * size.x + pixel.x;
  if (mask[index] != 0u) {
    blurred[index] = colour[index];
    return;
  }
  const float weights[3] = float[3](1.0, 0.60653066, 0.13533528);  // exp(-d^2 / 2), d = 0, 1, 2
  vec3 sum = vec3(0.0);
  float weight_sum = 0.0;
  bool transition = false;
  for (int dy = -2; dy <= 2; ++dy) {
    for (int dx = -2; dx <= 2; ++dx) {
      ivec2 neighbour = pixel + ivec2(dx, dy);
      if (any(lessThan(neighbour, ivec2(0))) || any(greaterThanEqual(neighbour, size))) continue;
      int neighbour_index = neighbour.y * size.x + neighbour.x;
      transition = transition || mask[neighbour_index] != 0u;
      float weight = weights[abs(dx)] * weights[abs(dy)];
      sum += weight * colour[neighbour_index].rgb;
      weight_sum += weight;
    }
  }
  blurred[index] = transition ? vec4(sum / weight_sum, 1.0) : colour[index];
}

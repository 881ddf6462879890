#version 460
// Pull-push (Gortler et al. 1996) fill of the linear model's frame: the shaded pixels have alpha 1,
// the rest 0. Pull: each coarser level is the alpha-weighted mean of its 2x2 children, its alpha the
// children's sum capped at 1. Push, coarse to fine: a pixel keeps its own colour in proportion to
// its alpha and takes the rest from the level above, read bilinearly; the finest level's result is
// the frame. All levels live in one buffer, the finest (the sample buffer, one entry a pixel) first.
#extension GL_GOOGLE_include_directive : require
#include "shared/sampling_params.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = 0) buffer Pyramid { vec4 pyramid[]; };
layout(std430, binding = 1) writeonly buffer FrameColour { vec4 frame_colour[]; };

layout(push_constant) uniform PullPushParamsBlock { PullPushParams params; };

void pull(uvec2 pixel) {
  vec4 sum = vec4(0.0);
  for (uint dy = 0u; dy < 2u; ++dy) {
    for (uint dx = 0u; dx < 2u; ++dx) {
      uvec2 child = pixel * 2u + uvec2(dx, dy);
      if (any(greaterThanEqual(child, params.fine_size))) continue;
      vec4 c = pyramid[params.fine_offset + child.y * params.fine_size.x + child.x];
      sum += c.a * vec4(c.rgb, 1.0);
    }
  }
  pyramid[params.coarse_offset + pixel.y * params.coarse_size.x + pixel.x] =
      sum.a > 0.0 ? vec4(sum.rgb / sum.a, min(sum.a, 1.0)) : vec4(0.0);
}

vec3 coarse_bilinear(vec2 coarse_px) {
  vec2 p = coarse_px - 0.5;
  vec2 base = floor(p);
  vec2 f = p - base;
  ivec2 last = ivec2(params.coarse_size) - 1;
  vec3 sum = vec3(0.0);
  for (int dy = 0; dy <= 1; ++dy) {
    for (int dx = 0; dx <= 1; ++dx) {
      ivec2 q = clamp(ivec2(base) + ivec2(dx, dy), ivec2(0), last);
      float w = (dx == 1 ? f.x : 1.0 - f.x) * (dy == 1 ? f.y : 1.0 - f.y);
      sum += w * pyramid[params.coarse_offset + uint(q.y) * params.coarse_size.x + uint(q.x)].rgb;
    }
  }
  return sum;
}

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (params.mode == 0u) {
    if (all(lessThan(pixel, params.coarse_size))) pull(pixel);
    return;
  }
  if (any(greaterThanEqual(pixel, params.fine_size))) return;
  uint index = params.fine_offset + pixel.y * params.fine_size.x + pixel.x;
  vec4 own = pyramid[index];
  vec3 colour = own.a >= 1.0 ? own.rgb : own.a * own.rgb + (1.0 - own.a) * coarse_bilinear((vec2(pixel) + 0.5) * 0.5);
  if (params.mode == 2u) frame_colour[pixel.y * params.fine_size.x + pixel.x] = vec4(colour, 1.0);
  else pyramid[index] = vec4(colour, 1.0);
}

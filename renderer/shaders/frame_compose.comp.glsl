#version 460
// A frame onto a presentation image (renderer/present/frame_compose.h): every image pixel is
// written, with the frame's pixel it shows (integer scale, centred, cropped) or opaque black
// (letterbox), in the image's byte order. One invocation an image pixel.
#extension GL_GOOGLE_include_directive : require
#include "shared/present_params.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Frame { uint frame_texels[]; };  // packed RGBA8
layout(std430, binding = 1) writeonly buffer Image { uint image_texels[]; };

layout(push_constant) uniform ComposeParamsBlock { ComposeParams params; };

const uint kOpaqueBlack = 0xff000000u;

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (pixel.x >= params.image_size.x || pixel.y >= params.image_size.y) return;
  ivec2 p = ivec2(pixel);
  uint value = kOpaqueBlack;
  if (all(greaterThanEqual(p, params.shown_min)) && all(lessThan(p, params.shown_max))) {
    uvec2 source = uvec2(p - params.offset) / params.scale;
    uint rgba = frame_texels[source.y * params.frame_size.x + source.x];
    value = params.bgra == 1u ? (rgba & 0xff00ff00u) | ((rgba & 0xffu) << 16) | ((rgba >> 16) & 0xffu) : rgba;
  }
  image_texels[pixel.y * params.image_size.x + pixel.x] = value;
}

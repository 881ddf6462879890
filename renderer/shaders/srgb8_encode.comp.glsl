#version 460
// Float RGBA texels to what a display shows: sRGB8, packed RGBA in one uint with alpha 255
// (srgb8.glsl); renderer/present/srgb8_encoder.h dispatches it. The one encoder of displayed frames:
// SphereTracer's display output (gt, ipr, fipr), and ZoneBlender's zones once an animation frame
// (zone_display then copies most pixels from there) and the pt method's frames, so that a pt frame
// and the fovea of the fpt frame made from it are the same bytes.
#extension GL_GOOGLE_include_directive : require

const uint OUTPUT_SRGB8 = 1u;

#include "srgb8.glsl"
#include "zone_texels.glsl"
#include "shared/present_params.h"
layout(local_size_x = ROW_GROUP_WIDTH, local_size_y = 1, local_size_z = 1) in;  // rows of 64, as zone_blend

layout(std430, binding = 1) writeonly buffer Encoded { uint encoded[]; };

layout(push_constant) uniform EncodeParamsBlock { EncodeParams params; };

void main() {
  uvec2 pixel = uvec2(gl_GlobalInvocationID.x, gl_GlobalInvocationID.y);
  if (pixel.x >= params.image_size.x) return;
  uint index = pixel.y * params.image_size.x + pixel.x;
  encoded[index] = packed_srgb8(texel(index));
}

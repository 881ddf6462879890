#version 460
// What a participant sees for one gaze sample, second pass (ZoneBlender::display_frame): the band
// pixels zone_display listed, blended from the float zones by their exact eccentricity and encoded
// to sRGB8 (zone_blend's blend, srgb8_encode's encoding). Dispatched indirectly (list_dispatch):
// workgroup (x, y) of 64 takes list items from (y * groups_x + x) * 64.
#extension GL_GOOGLE_include_directive : require

const uint OUTPUT_SRGB8 = 1u;

#include "srgb8.glsl"
#include "zone_weights.glsl"
#include "zone_texels.glsl"
layout(local_size_x = ROW_GROUP_WIDTH, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 1) writeonly buffer BlendedSrgb8 { uint blended_srgb8[]; };
layout(std430, binding = 2) readonly buffer BandList {
  uint band_count;
  uint band_pixels[];
};

void main() {
  uint item = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationIndex;
  if (item >= band_count) return;
  uint packed_pixel = band_pixels[item];  // x | y << 16: no integer division here
  uvec2 pixel = uvec2(packed_pixel & 0xFFFFu, packed_pixel >> 16);
  uint index = pixel.y * params.frame_size.x + pixel.x;
  const uint zone_texels = params.frame_size.x * params.frame_size.y;
  blended_srgb8[index] = packed_srgb8(blend_texels(zone_weights(pixel_rays(pixel)), index, zone_texels));
}

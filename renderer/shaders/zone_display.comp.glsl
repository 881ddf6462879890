#version 460
// What a participant sees for one gaze sample, first of two passes (ZoneBlender::display_frame):
// a pixel outside the bands shows one zone's texel as it is, so it is copied from the zones
// encoded to sRGB8 once an animation frame (by srgb8_encode); a pixel in a band is listed for
// zone_band, which blends it. No arctangent, no sRGB curve and one 4-byte load here: the
// per-sample cost of most pixels is a copy's. (On lavapipe every branch runs for every pixel under
// a mask, so the band's work must be in a pass of its own to be skipped.)
#extension GL_GOOGLE_include_directive : require

#include "zone_weights.glsl"
layout(local_size_x = ROW_GROUP_WIDTH, local_size_y = 1, local_size_z = 1) in;

// The zones' sRGB8 texels (packed RGBA) one after the other: foveal, middle, outer.
layout(std430, binding = 0) readonly buffer ZonesSrgb8 { uint zones_srgb8[]; };
layout(std430, binding = 1) writeonly buffer BlendedSrgb8 { uint blended_srgb8[]; };
// The band pixels, x | y << 16 each (frames are at most 16384 pixels a side), in no particular
// order; band_count zeroed before.
layout(std430, binding = 2) buffer BandList {
  uint band_count;
  uint band_pixels[];
};

void main() {
  uvec2 pixel = uvec2(gl_GlobalInvocationID.x, gl_GlobalInvocationID.y);
  if (pixel.x >= params.frame_size.x) return;
  uint index = pixel.y * params.frame_size.x + pixel.x;
  float tan2 = pixel_rays(pixel).tan2;
  if (in_band(tan2)) {
    band_pixels[atomicAdd(band_count, 1u)] = pixel.x | (pixel.y << 16);
  } else {
    blended_srgb8[index] = zones_srgb8[core_zone(tan2) * params.frame_size.x * params.frame_size.y + index];
  }
}

#version 460
// The gaze-contingent three-zone blend of the emulated foveated path tracer (Polychronakis et al. 2021 section 3.2),
// in linear light, every pixel of the frame: each mixes the full-resolution (foveal), upsampled 1/4
// (middle) and upsampled 1/16 (outer) buffers by its exact eccentricity from the gaze
// (zone_weights.glsl), all four channels in float (previews, tests). What a session shows is the
// same blend sRGB-encoded, made by two cheaper passes: zone_display, then zone_band.
//
// One invocation a pixel in row-major order: a workgroup covers 64 consecutive pixels of a row,
// which lavapipe runs far faster than 8x8 tiles (contiguous SIMD loads and stores).
#extension GL_GOOGLE_include_directive : require

const uint OUTPUT_SRGB8 = 0u;

#include "zone_weights.glsl"
#include "zone_texels.glsl"
layout(local_size_x = ROW_GROUP_WIDTH, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 1) writeonly buffer Blended { vec4 blended[]; };

void main() {
  uvec2 pixel = uvec2(gl_GlobalInvocationID.x, gl_GlobalInvocationID.y);
  if (pixel.x >= params.frame_size.x) return;
  uint index = pixel.y * params.frame_size.x + pixel.x;
  blended[index] = blend_texels(zone_weights(pixel_rays(pixel)), index, params.frame_size.x * params.frame_size.y);
}

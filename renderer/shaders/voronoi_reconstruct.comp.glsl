#version 460
// The foveated volume frame rebuilt from its sites (Bruder et al. 2019 section 4.3): every screen pixel takes
// the Sibson-weighted sum of its natural neighbours' colours, read from the precomputed weights of
// its mask pixel (foveation/voronoi_reconstruction.h; the mask is the screen shifted by whole
// pixels with the gaze). Then the temporal smoothing (section 4.4): the output is the mean of this
// frame and the stored ones (history_count of them), and this frame is stored in slot store_slot
// when it is to be kept (renderer/volume/volume_raycaster.cpp decides when).
#extension GL_GOOGLE_include_directive : require
#include "shared/volume_params.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(push_constant) uniform VoronoiReconstructParamsBlock { VoronoiReconstructParams params; };

// 8 a mask pixel, heaviest first: the site's index in the low 20 bits, its weight in 1/4095 in the
// high 12 (0: an unused entry). One load a neighbour, and the colour two more: the pass reads little.
layout(std430, binding = 0) readonly buffer Neighbours { uint neighbours[]; };
layout(std430, binding = 1) readonly buffer SiteColours { uvec2 site_colours[]; };  // RGB as half floats
layout(std430, binding = 2) writeonly buffer Colour { vec4 colour[]; };             // the frame shown
layout(std430, binding = 3) buffer History { vec4 history[]; };                      // 8 frames

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (pixel.x >= params.screen_size.x || pixel.y >= params.screen_size.y) return;
  uvec2 mask_pixel = uvec2(ivec2(pixel) + params.mask_offset);
  uint base = (mask_pixel.y * params.mask_size.x + mask_pixel.x) * 8u;
  vec3 sum = vec3(0.0);
  float weight_sum = 0.0;
  for (uint k = 0u; k < 8u; ++k) {
    uint entry = neighbours[base + k];
    float weight = float(entry >> 20u);
    if (weight == 0.0) break;  // heaviest first: the rest are unused entries
    uvec2 packed = site_colours[entry & 0xFFFFFu];
    sum += weight * vec3(unpackHalf2x16(packed.x), unpackHalf2x16(packed.y).x);
    weight_sum += weight;
  }
  vec3 current = weight_sum > 0.0 ? sum / weight_sum : vec3(0.0);
  uint frame_pixels = params.screen_size.x * params.screen_size.y;
  uint index = pixel.y * params.screen_size.x + pixel.x;
  vec3 total = current;
  for (uint k = 0u; k < params.history_count; ++k) total += history[k * frame_pixels + index].rgb;
  colour[index] = vec4(total / float(params.history_count + 1u), 1.0);
  if (params.store_slot != 0xFFFFFFFFu) history[params.store_slot * frame_pixels + index] = vec4(current, 1.0);
}

#version 460
// FIPR pass 4, reconstruction of the pixels outside the mask (Polychronakis et al. 2023 section 3.2.4) when they take
// the mid level's colour (periphery_steps 0): a pixel that is due for a refresh gets the mid level's
// colour, interpolated by Catmull-Rom over the 4x4 mid pixels around it (catmull_rom 1, when all 16
// are fresh) or bilinearly; in the bilinear form, mid pixels not shaded within the refresh period
// (alpha 0: all their children were traced at the top level) are left out and the weights
// renormalised; the pixel's own parent was just shaded, so one tap always counts. A pixel that is
// not due keeps the colour it has (the colour buffer persists between frames). Masked pixels are the
// top level's, left alone. The refresh phases are those of fovlab_refresh_due in sphere_trace.comp.glsl.
#extension GL_GOOGLE_include_directive : require
#include "shared/fipr_params.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Mask { uint mask[]; };
layout(std430, binding = 1) readonly buffer MidFlags { uint mid_flags[]; };  // bit 8: due for a refresh
layout(std430, binding = 2) readonly buffer MidColour { vec4 mid_colour[]; };
layout(std430, binding = 3) buffer Colour { vec4 colour[]; };

layout(push_constant) uniform FiprReconstructParamsBlock { FiprReconstructParams params; };

bool fresh(vec4 value, float newest) { return value.a > 0.0 && newest - value.a < float(params.refresh_period); }

// Catmull-Rom's weights of the taps at -1, 0, 1, 2 for a position f in [0, 1) between taps 0 and 1.
vec4 catmull_rom_weights(float f) {
  return vec4(((-0.5 * f + 1.0) * f - 0.5) * f, (1.5 * f - 2.5) * f * f + 1.0, ((-1.5 * f + 2.0) * f + 0.5) * f,
              (0.5 * f - 0.5) * f * f);
}

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, params.frame_size))) return;
  uint index = pixel.y * params.frame_size.x + pixel.x;
  if (mask[index] != 0u) return;
  uvec2 parent = pixel / 2u;
  if ((mid_flags[parent.y * params.mid_size.x + parent.x] & MID_FLAG_DUE) == 0u) return;
  float newest = float(params.frame_index + 1u);
  vec2 position = (vec2(pixel) + 0.5) * 0.5 - 0.5;  // in mid-level pixel centres
  ivec2 base = ivec2(floor(position));
  vec2 f = position - vec2(base);
  ivec2 last = ivec2(params.mid_size) - 1;
  if (params.catmull_rom != 0u) {
    vec4 wx = catmull_rom_weights(f.x);
    vec4 wy = catmull_rom_weights(f.y);
    vec3 cubic = vec3(0.0);
    bool all_fresh = true;
    for (int j = 0; j < 4; ++j) {
      for (int i = 0; i < 4; ++i) {
        ivec2 tap = clamp(base + ivec2(i - 1, j - 1), ivec2(0), last);
        vec4 value = mid_colour[tap.y * int(params.mid_size.x) + tap.x];
        all_fresh = all_fresh && fresh(value, newest);
        cubic += wx[i] * wy[j] * value.rgb;
      }
    }
    if (all_fresh) {
      colour[index] = vec4(max(cubic, vec3(0.0)), 1.0);  // (its negative lobes may undershoot black)
      return;
    }
  }
  vec3 sum = vec3(0.0);
  float weight_sum = 0.0;
  for (int j = 0; j <= 1; ++j) {
    for (int i = 0; i <= 1; ++i) {
      ivec2 tap = clamp(base + ivec2(i, j), ivec2(0), last);
      vec4 value = mid_colour[tap.y * int(params.mid_size.x) + tap.x];
      float weight = fresh(value, newest) ? (i == 1 ? f.x : 1.0 - f.x) * (j == 1 ? f.y : 1.0 - f.y) : 0.0;
      sum += weight * value.rgb;
      weight_sum += weight;
    }
  }
  colour[index] = vec4(weight_sum > 0.0 ? sum / weight_sum : mid_colour[parent.y * params.mid_size.x + parent.x].rgb, 1.0);
}

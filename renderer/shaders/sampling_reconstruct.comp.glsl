#version 460
// Pass 2 of the sampling models (Ye et al. 2022): each screen pixel from the shaded samples.
//   - RMFR: the forward map gives the pixel's place in the reduced buffer, read bilinearly (or with
//     Lanczos-2, the parameters' resample_filter);
//   - KFR: the same in the log-polar buffer (its angle wraps around);
//   - hyperbolic: each layer with weight at the pixel is read the same way, the reads blended.
// (The linear model's pixels are filled by pull_push.comp.glsl instead.) A sample that was not
// shaded has alpha 0 and is left out of the bilinear weights, so a pixel never reads a stale value.
// foveation/sampling_map.cpp is the reference of the maps and weights.
#extension GL_GOOGLE_include_directive : require
#include "eccentricity.glsl"
#include "sampling_map.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = 1) writeonly buffer FrameColour { vec4 frame_colour[]; };
// The shaded samples (alpha 1: shaded), read through a texel view of their buffer: lavapipe fetches
// texels with vector gathers, where a storage buffer's loads run lane by lane (its per-pass table in
// docs/benchmarks.md, issue 41). The same floats either way.
layout(binding = 2) uniform samplerBuffer sample_colours;

vec4 sample_colour(uint index) { return texelFetch(sample_colours, int(index)); }

layout(push_constant) uniform SamplingReconstructParamsBlock { SamplingReconstructParams params; };

// The model and filter this pipeline serves, fixed when SamplingPasses makes it (MODEL_*, FILTER_*;
// they equal the parameters' model and resample_filter). Why constants: lavapipe runs both sides of a
// branch under a mask, so with the model read at run time every pixel paid for the other models' maps
// and reads, and for the filter it does not use.
layout(constant_id = 0) const uint RECONSTRUCT_MODEL = MODEL_RECTANGULAR;
layout(constant_id = 1) const uint RECONSTRUCT_FILTER = FILTER_BILINEAR;

// The Lanczos-2 kernel sinc(x) sinc(x / 2) on |x| < 2.
float lanczos2(float x) {
  if (abs(x) < 1e-5) return 1.0;
  if (abs(x) >= 2.0) return 0.0;
  float pi_x = 3.14159265359 * x;
  return 2.0 * sin(pi_x) * sin(0.5 * pi_x) / (pi_x * pi_x);
}

// Bilinear read (2x2 taps) of a grid of `grid_size` samples stored row-major from `first`, at a
// continuous position in grid pixels (sample centres at + 0.5), each tap weighted by its alpha (0:
// not shaded). Columns clamp; rows clamp or wrap. Returns the colour and the weight of the shaded
// taps (0: none was shaded). Straight-line code: the common case and most of a frame's cost, kept
// apart from the Lanczos loop.
vec4 grid_read_bilinear(uint first, uvec2 grid_size, vec2 grid_px, bool wrap_rows) {
  vec2 p = grid_px - 0.5;
  vec2 base = floor(p);
  vec2 f = p - base;
  ivec2 size = ivec2(grid_size);
  ivec2 q0 = ivec2(base);
  int x0 = clamp(q0.x, 0, size.x - 1), x1 = clamp(q0.x + 1, 0, size.x - 1);
  int y0 = wrap_rows ? ((q0.y % size.y) + size.y) % size.y : clamp(q0.y, 0, size.y - 1);
  int y1 = wrap_rows ? (y0 + 1) % size.y : clamp(q0.y + 1, 0, size.y - 1);
  uint row0 = first + uint(y0) * grid_size.x, row1 = first + uint(y1) * grid_size.x;
  vec4 c00 = sample_colour(row0 + uint(x0)), c10 = sample_colour(row0 + uint(x1));
  vec4 c01 = sample_colour(row1 + uint(x0)), c11 = sample_colour(row1 + uint(x1));
  vec4 sum = ((1.0 - f.x) * (1.0 - f.y) * c00.a) * vec4(c00.rgb, 1.0) + (f.x * (1.0 - f.y) * c10.a) * vec4(c10.rgb, 1.0) +
             ((1.0 - f.x) * f.y * c01.a) * vec4(c01.rgb, 1.0) + (f.x * f.y * c11.a) * vec4(c11.rgb, 1.0);
  if (!(sum.a > 0.0)) return vec4(0.0);
  return vec4(sum.rgb / sum.a, sum.a);
}

// The same read with the parameters' filter: bilinear, or Lanczos-2 (4x4 taps, alpha-weighted the
// same way).
vec4 grid_read(uint first, uvec2 grid_size, vec2 grid_px, bool wrap_rows) {
  if (RECONSTRUCT_FILTER != FILTER_LANCZOS2) return grid_read_bilinear(first, grid_size, grid_px, wrap_rows);
  vec2 p = grid_px - 0.5;
  vec2 base = floor(p);
  vec2 f = p - base;
  ivec2 size = ivec2(grid_size);
  vec4 sum = vec4(0.0);
  vec3 lowest = vec3(3.0e38), highest = vec3(-3.0e38);  // of the shaded taps
  for (int dy = -1; dy <= 2; ++dy) {
    for (int dx = -1; dx <= 2; ++dx) {
      ivec2 q = ivec2(base) + ivec2(dx, dy);
      q.x = clamp(q.x, 0, size.x - 1);
      q.y = wrap_rows ? ((q.y % size.y) + size.y) % size.y : clamp(q.y, 0, size.y - 1);
      float w = lanczos2(float(dx) - f.x) * lanczos2(float(dy) - f.y);
      vec4 c = sample_colour(first + uint(q.y) * grid_size.x + uint(q.x));
      sum += w * c.a * vec4(c.rgb, 1.0);
      if (c.a > 0.0) {
        lowest = min(lowest, c.rgb);
        highest = max(highest, c.rgb);
      }
    }
  }
  // The negative lobes can leave a weight near 0 where taps are missing (treated as none) and
  // overshoot at edges (clamped to the taps' range).
  if (!(sum.a > 1e-3)) return vec4(0.0);
  return vec4(clamp(sum.rgb / sum.a, lowest, highest), sum.a);
}

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, sampling.screen_size))) return;
  vec2 centre = vec2(pixel) + 0.5;
  vec2 screen = vec2(sampling.screen_size);
  vec4 colour = vec4(0.0);
  if (RECONSTRUCT_MODEL == MODEL_RECTANGULAR) {
    vec2 share = centre / screen;
    vec2 buffer_share = vec2(rmfr_to_buffer(share.x, sampling.gaze_share.x, sampling.focal_share.x),
                             rmfr_to_buffer(share.y, sampling.gaze_share.y, sampling.focal_share.y));
    colour = grid_read(0u, sampling.buffer_size, buffer_share * vec2(sampling.buffer_size), false);
  } else if (RECONSTRUCT_MODEL == MODEL_KERNEL_LOG_POLAR) {
    colour = grid_read(0u, sampling.buffer_size, kfr_to_buffer_px(centre), true);
  } else if (RECONSTRUCT_MODEL == MODEL_HYPERBOLIC) {
    vec3 weights = hyperbolic_weights(centre);
    vec4 sum = vec4(0.0);
    for (int i = 0; i < 3; ++i) {
      if (weights[i] <= 0.0) continue;
      SamplingLayer layer = sampling.layers[i];
      if (layer.grid_size.x == 0u || layer.grid_size.y == 0u) continue;
      vec4 read = grid_read(layer.first_sample, layer.grid_size, (centre - layer.origin_px) / layer.pixel_size_px,
                                false);
      if (read.a > 0.0) sum += weights[i] * vec4(read.rgb, 1.0);
    }
    colour = sum.a > 0.0 ? vec4(sum.rgb / sum.a, 1.0) : vec4(0.0);
  }
  frame_colour[pixel.y * sampling.screen_size.x + pixel.x] = vec4(colour.rgb, 1.0);
}

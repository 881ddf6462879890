#version 460
// One axis of the separable upsampling of a zone buffer (renderer/upsampling/upsample_filter.h has
// the definitions and the double-precision reference): output pixel i along the axis reads the
// input at u = (i + 0.5) / factor - 0.5, taps outside the input repeat its edge, and the weights of
// the filter (Lanczos-3, bilinear or nearest) are normalised to sum to 1. They depend only on
// i mod factor and come precomputed in double (upsample_weights): six taps, floor(u) - 2 to
// floor(u) + 3. Run along x, then y.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Source { vec4 source[]; };
layout(std430, binding = 1) writeonly buffer Target { vec4 target[]; };
layout(std430, binding = 2) readonly buffer Weights { float weights[]; };  // factor x 6

layout(push_constant) uniform UpsampleParams {
  uvec2 source_size;
  uvec2 target_size;  // source_size scaled by factor along `axis`
  uint factor;
  uint axis;          // 0: x, 1: y
} params;

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, params.target_size))) return;
  int out_coordinate = int(params.axis == 0u ? pixel.x : pixel.y);
  int length = int(params.axis == 0u ? params.source_size.x : params.source_size.y);
  // floor(u) = floor((2 i + 1 - factor) / (2 factor)), exactly, in integers.
  int twice_factor = int(2u * params.factor);
  int numerator = 2 * out_coordinate + 1 - int(params.factor);
  int base = numerator >= 0 ? numerator / twice_factor : -((-numerator + twice_factor - 1) / twice_factor);
  uint phase = uint(out_coordinate) % params.factor;
  vec4 sum = vec4(0.0);
  for (int k = -2; k <= 3; ++k) {
    int tap = clamp(base + k, 0, length - 1);
    uvec2 source_pixel = params.axis == 0u ? uvec2(uint(tap), pixel.y) : uvec2(pixel.x, uint(tap));
    sum += weights[phase * 6u + uint(k + 2)] * source[source_pixel.y * params.source_size.x + source_pixel.x];
  }
  target[pixel.y * params.target_size.x + pixel.x] = sum;
}

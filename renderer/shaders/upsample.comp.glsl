#version 460
// One axis of the separable upsampling of a zone buffer (renderer/upsampling/upsample_filter.h has
// the definitions and the double-precision reference): output pixel i along the axis reads the
// input at u = (i + 0.5) / factor - 0.5, taps outside the input repeat its edge, and the weights of
// the filter (Lanczos-3, bilinear or nearest) are normalised to sum to 1. Run along x, then y.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Source { vec4 source[]; };
layout(std430, binding = 1) writeonly buffer Target { vec4 target[]; };

const uint FILTER_LANCZOS3 = 0u;
const uint FILTER_BILINEAR = 1u;
const uint FILTER_NEAREST = 2u;
const float PI = 3.14159265358979;

layout(push_constant) uniform UpsampleParams {
  uvec2 source_size;
  uvec2 target_size;  // source_size scaled by factor along `axis`
  uint factor;
  uint axis;          // 0: x, 1: y
  uint filter_kind;
} params;

float sinc(float t) {
  if (t == 0.0) return 1.0;
  float x = PI * t;
  return sin(x) / x;
}

float kernel(float t) {
  if (params.filter_kind == FILTER_LANCZOS3) return abs(t) < 3.0 ? sinc(t) * sinc(t / 3.0) : 0.0;
  if (params.filter_kind == FILTER_BILINEAR) return max(0.0, 1.0 - abs(t));
  return (t >= -0.5 && t < 0.5) ? 1.0 : 0.0;
}

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, params.target_size))) return;
  int out_coordinate = int(params.axis == 0u ? pixel.x : pixel.y);
  int length = int(params.axis == 0u ? params.source_size.x : params.source_size.y);
  // u = (i + 0.5) / factor - 0.5 split into an integer and a fraction exactly: i + 0.5 - factor / 2
  // over factor, so the taps' offsets are exact small fractions.
  int numerator = 2 * out_coordinate + 1 - int(params.factor);  // 2 factor u
  int base = numerator >= 0 ? numerator / int(2u * params.factor) : -((-numerator + int(2u * params.factor) - 1) / int(2u * params.factor));
  float fraction = float(numerator - base * int(2u * params.factor)) / float(2u * params.factor);
  int radius = params.filter_kind == FILTER_LANCZOS3 ? 3 : 1;
  vec4 sum = vec4(0.0);
  float weight_sum = 0.0;
  for (int k = 1 - radius; k <= radius; ++k) {
    float weight = kernel(fraction - float(k));
    int tap = clamp(base + k, 0, length - 1);
    uvec2 source_pixel = params.axis == 0u ? uvec2(uint(tap), pixel.y) : uvec2(pixel.x, uint(tap));
    sum += weight * source[source_pixel.y * params.source_size.x + source_pixel.x];
    weight_sum += weight;
  }
  target[pixel.y * params.target_size.x + pixel.x] = sum / weight_sum;
}

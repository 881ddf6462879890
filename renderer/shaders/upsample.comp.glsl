#version 460
// One axis of the separable upsampling of a zone buffer (renderer/upsampling/upsample_filter.h has
// the definitions and the double-precision reference): output pixel i along the axis reads the
// input at u = (i + 0.5) / factor - 0.5, taps outside the input repeat its edge, and the weights of
// the filter (Lanczos-3, bilinear or nearest) are normalised to sum to 1. Run along x, then y.
//
// The `factor` outputs of one input cell c (outputs c * factor to c * factor + factor - 1) take
// their six taps from the seven input pixels c - 3 .. c + 3; the weights come precomputed in double
// (upsample_cell_weights): seven per phase, zero where a phase does not reach. One invocation runs
// along one line (a row for x, a column for y) through CELLS_PER_INVOCATION consecutive cells,
// sliding its seven taps by one pixel a cell, so each input pixel is read about once; neighbouring
// invocations take neighbouring lines.
//
// The target may be cropped: target_size along the axis may be less than factor times the source
// (a frame whose sides are not multiples of the factor has zone buffers rounded up); outputs past
// it are not written, and the others are exactly those of the uncropped image.
#extension GL_GOOGLE_include_directive : require
#include "shared/upsample_params.h"
layout(local_size_x = ROW_GROUP_WIDTH, local_size_y = 1, local_size_z = 1) in;


layout(std430, binding = 0) readonly buffer Source { vec4 source[]; };
layout(std430, binding = 1) writeonly buffer Target { vec4 target[]; };
layout(std430, binding = 2) readonly buffer Weights { float weights[]; };  // factor x 7

layout(push_constant) uniform UpsampleParamsBlock { UpsampleParams params; };

void main() {
  uint line = gl_GlobalInvocationID.x;
  uint first_cell = gl_GlobalInvocationID.y * CELLS_PER_INVOCATION;
  uint cells = params.axis == 0u ? params.source_size.x : params.source_size.y;
  uint lines = params.axis == 0u ? params.source_size.y : params.source_size.x;
  if (line >= lines || first_cell >= cells) return;
  // Texel index of (position along the axis, this line) in the source and the target.
  uint source_stride = params.axis == 0u ? 1u : params.source_size.x;
  uint source_line = params.axis == 0u ? line * params.source_size.x : line;
  uint target_stride = params.axis == 0u ? 1u : params.target_size.x;
  uint target_extent = params.axis == 0u ? params.target_size.x : params.target_size.y;
  uint target_line = params.target_offset + (params.axis == 0u ? line * params.target_size.x : line);
  int last = int(cells) - 1;

  vec4 taps[7];
  for (int j = 0; j < 7; ++j) taps[j] = source[source_line + uint(clamp(int(first_cell) + j - 3, 0, last)) * source_stride];
  uint end_cell = min(first_cell + CELLS_PER_INVOCATION, cells);
  for (uint cell = first_cell; cell < end_cell; ++cell) {
    if (cell > first_cell) {
      for (int j = 0; j < 6; ++j) taps[j] = taps[j + 1];
      taps[6] = source[source_line + uint(clamp(int(cell) + 3, 0, last)) * source_stride];
    }
    for (uint phase = 0u; phase < params.factor; ++phase) {
      if (cell * params.factor + phase >= target_extent) break;
      vec4 sum = vec4(0.0);
      for (int j = 0; j < 7; ++j) sum += weights[phase * 7u + uint(j)] * taps[j];
      target[target_line + (cell * params.factor + phase) * target_stride] = sum;
    }
  }
}

#ifndef FOVLAB_PRESENT_PARAMS_H
#define FOVLAB_PRESENT_PARAMS_H
// The push constants of present/'s passes (srgb8_encode.comp.glsl, frame_compose.comp.glsl).
#include "gpu_types.h"

FOVLAB_GPU_BEGIN

struct EncodeParams {
  uvec2 image_size;
};

struct ComposeParams {
  uvec2 frame_size;
  uvec2 image_size;
  ivec2 shown_min;  // the image rectangle [shown_min, shown_max) shows the frame
  ivec2 shown_max;
  ivec2 offset;  // image pixel p shows scaled frame pixel p - offset
  uint scale;
  uint bgra;  // 1: swap R and B (B8G8R8A8 images)
};

FOVLAB_GPU_END

#endif

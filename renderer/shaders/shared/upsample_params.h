#ifndef FOVLAB_UPSAMPLE_PARAMS_H
#define FOVLAB_UPSAMPLE_PARAMS_H
// upsample.comp.glsl's push constants and work split; Upsampler fills them (renderer/upsampling/).
#include "gpu_types.h"

FOVLAB_GPU_BEGIN

const uint CELLS_PER_INVOCATION = 8u;  // cells along the axis that one invocation writes

struct UpsampleParams {
  uvec2 source_size;
  uvec2 target_size;  // source_size scaled by factor along `axis`, or less (cropped at the far edge)
  uint factor;
  uint axis;           // 0: x, 1: y
  uint target_offset;  // texels before the target image in its buffer (a zone of ZoneBlender's buffer)
};

FOVLAB_GPU_END

#endif

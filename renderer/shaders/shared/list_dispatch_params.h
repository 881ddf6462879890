#ifndef FOVLAB_LIST_DISPATCH_PARAMS_H
#define FOVLAB_LIST_DISPATCH_PARAMS_H
// list_dispatch.comp.glsl's push constants: the indirect dispatch of one or two counted lists.
#include "gpu_types.h"

FOVLAB_GPU_BEGIN

struct ListParams {
  uvec2 counter_index;  // counters[counter_index[i]] counts list i
  uint list_count;      // 1 or 2
};

FOVLAB_GPU_END

#endif

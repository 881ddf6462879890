#version 460
// The workgroup counts of dispatches over lists that an earlier pass filled (64 items a workgroup),
// for vkCmdDispatchIndirect: list i's length is counters[counter_index[i]], its counts go to
// group_counts[3 i .. 3 i + 2]. Spread over x and y, since only 65535 workgroups a dimension are
// guaranteed; the list's shader numbers a workgroup y * groups_x + x. FIPR's top level has two
// lists (the masked pixels and the unmasked ones due for a refresh), its mid level one (the pixels it
// traces), the zone blend's band pass one.
#extension GL_GOOGLE_include_directive : require
#include "shared/list_dispatch_params.h"

layout(local_size_x = 1, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Counters { uint counters[]; };
layout(std430, binding = 1) writeonly buffer DispatchArguments { uint group_counts[]; };

layout(push_constant) uniform ListParamsBlock { ListParams params; };

const uint MAX_GROUPS_X = 65535u;

void write_counts(uint first, uint items) {
  uint groups = (items + 63u) / 64u;
  group_counts[first] = min(groups, MAX_GROUPS_X);
  group_counts[first + 1u] = (groups + MAX_GROUPS_X - 1u) / MAX_GROUPS_X;
  group_counts[first + 2u] = 1u;
}

void main() {
  write_counts(0u, counters[params.counter_index.x]);
  if (params.list_count > 1u) write_counts(3u, counters[params.counter_index.y]);
}

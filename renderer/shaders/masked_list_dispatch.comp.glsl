#version 460
// FIPR: the workgroup counts of the top level's dispatches over the lists of the mask pass (64
// pixels a workgroup): the masked pixels (count in counters[2]) and the unmasked pixels due for a
// refresh (counters[6]). Spread over x and y, since only 65535 workgroups a dimension are
// guaranteed; the trace shader numbers a workgroup y * groups_x + x.
layout(local_size_x = 1, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Counters { uint counters[]; };
layout(std430, binding = 1) writeonly buffer DispatchArguments { uint group_counts[6]; };

const uint MAX_GROUPS_X = 65535u;

void write_counts(uint first, uint pixels) {
  uint groups = (pixels + 63u) / 64u;
  group_counts[first] = min(groups, MAX_GROUPS_X);
  group_counts[first + 1u] = (groups + MAX_GROUPS_X - 1u) / MAX_GROUPS_X;
  group_counts[first + 2u] = 1u;
}

void main() {
  write_counts(0u, counters[2]);
  write_counts(3u, counters[6]);
}

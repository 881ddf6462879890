#pragma once
// A bounding volume hierarchy over a PathScene's triangles, built on the CPU with a binned surface
// area heuristic and flattened depth-first for the GPU (renderer/shaders/path_trace.comp.glsl reads
// the nodes as they are, so the layout is std430's).
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/shaders/shared/path_trace_params.h"

namespace fovlab {

struct PathScene;

using BvhNode = gpu::BvhNode;  // what path_trace.comp.glsl reads

struct Bvh {
  std::vector<BvhNode> nodes;            // nodes[0] is the root
  std::vector<uint32_t> triangle_order;  // leaf slots -> scene triangle index
  int depth = 0;                         // levels, the root's included (traversal stacks need depth - 1 entries)
};

// Deepest tree build_bvh makes; a node at this depth becomes a leaf whatever its size. The shader's
// traversal stack holds kBvhMaxDepth entries.
constexpr int kBvhMaxDepth = 48;

// Leaves hold at most 4 triangles (more only at kBvhMaxDepth or when all centroids coincide). The
// scene must be valid (validate(const PathScene&)).
Bvh build_bvh(const PathScene& scene);

}  // namespace fovlab

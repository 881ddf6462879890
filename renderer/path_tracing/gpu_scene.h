#pragma once
// A PathScene and its Bvh packed into the arrays the shader reads (std430 layouts of
// renderer/shaders/path_trace.comp.glsl): triangles in BVH leaf order with precomputed edges,
// materials, and the table of emitters that next-event estimation picks from.
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/path_tracing/bvh.h"

namespace fovlab {

struct PathScene;

// The scene as path_trace.comp.glsl reads it (renderer/shaders/shared/path_trace_params.h).
using GpuTriangle = gpu::Triangle;
using GpuMaterial = gpu::Material;
using GpuEmitter = gpu::Emitter;

struct PackedScene {
  std::vector<BvhNode> nodes;
  std::vector<GpuTriangle> triangles;
  std::vector<GpuMaterial> materials;
  std::vector<GpuEmitter> emitters;  // empty when nothing emits (zero-area emitters are left out)
};

PackedScene pack_scene(const PathScene& scene, const Bvh& bvh);

}  // namespace fovlab

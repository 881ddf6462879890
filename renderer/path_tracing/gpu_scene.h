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

struct GpuTriangle {
  glm::vec3 v0{0.0f};
  uint32_t material = 0;
  glm::vec3 edge1{0.0f};          // v1 - v0
  float light_pdf_per_area = 0;   // emitters: probability of picking this triangle / its area; else 0
  glm::vec3 edge2{0.0f};          // v2 - v0
  uint32_t scene_triangle = 0;    // index in the PathScene
};
static_assert(sizeof(GpuTriangle) == 48, "GpuTriangle must match the shader's std430 layout");

struct GpuMaterial {
  glm::vec3 colour{0.0f};
  uint32_t kind = 0;  // MaterialKind
  float index_of_refraction = 1.0f;
  float unused[3] = {0, 0, 0};
};
static_assert(sizeof(GpuMaterial) == 32, "GpuMaterial must match the shader's std430 layout");

// Emitters are picked with probability proportional to area x mean emitted radiance: the first
// entry whose cdf exceeds a uniform number in [0, 1).
struct GpuEmitter {
  uint32_t slot = 0;  // index into PackedScene::triangles
  float cdf = 0.0f;   // cumulative probability up to and including this emitter; the last is 1
  float unused[2] = {0, 0};
};
static_assert(sizeof(GpuEmitter) == 16, "GpuEmitter must match the shader's std430 layout");

struct PackedScene {
  std::vector<BvhNode> nodes;
  std::vector<GpuTriangle> triangles;
  std::vector<GpuMaterial> materials;
  std::vector<GpuEmitter> emitters;  // empty when nothing emits (zero-area emitters are left out)
};

PackedScene pack_scene(const PathScene& scene, const Bvh& bvh);

}  // namespace fovlab

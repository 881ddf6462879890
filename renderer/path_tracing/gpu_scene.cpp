#include "renderer/path_tracing/gpu_scene.h"

#include <glm/geometric.hpp>

#include "renderer/path_tracing/path_scene.h"

namespace fovlab {

PackedScene pack_scene(const PathScene& scene, const Bvh& bvh) {
  PackedScene packed;
  packed.nodes = bvh.nodes;
  for (const PathMaterial& material : scene.materials) {
    GpuMaterial gpu{};
    gpu.colour = material.colour;
    gpu.kind = static_cast<uint32_t>(material.kind);
    gpu.index_of_refraction = material.index_of_refraction;
    packed.materials.push_back(gpu);
  }
  std::vector<double> weights;  // per emitter, in slot order
  std::vector<double> areas;
  packed.triangles.resize(bvh.triangle_order.size());
  for (size_t slot = 0; slot < bvh.triangle_order.size(); ++slot) {
    const uint32_t t = bvh.triangle_order[slot];
    const glm::vec3 a = scene.positions[scene.indices[3 * size_t(t)]];
    const glm::vec3 b = scene.positions[scene.indices[3 * size_t(t) + 1]];
    const glm::vec3 c = scene.positions[scene.indices[3 * size_t(t) + 2]];
    GpuTriangle& gpu = packed.triangles[slot];
    gpu.v0 = a;
    gpu.edge1 = b - a;
    gpu.edge2 = c - a;
    gpu.material = scene.material_per_triangle[t];
    gpu.scene_triangle = t;
    const PathMaterial& material = scene.materials[gpu.material];
    if (material.kind != MaterialKind::emissive) continue;
    const glm::dvec3 e1(gpu.edge1), e2(gpu.edge2);
    const double area = 0.5 * glm::length(glm::cross(e1, e2));
    const double radiance = (double(material.colour.x) + double(material.colour.y) + double(material.colour.z)) / 3.0;
    if (!(area > 0.0 && radiance > 0.0)) continue;
    packed.emitters.push_back(GpuEmitter{uint32_t(slot), 0.0f, 0.0f, 0.0f});
    weights.push_back(area * radiance);
    areas.push_back(area);
  }
  double total = 0.0;
  for (double w : weights) total += w;
  double running = 0.0;
  for (size_t e = 0; e < packed.emitters.size(); ++e) {
    running += weights[e];
    packed.emitters[e].cdf = e + 1 == packed.emitters.size() ? 1.0f : float(running / total);
    packed.triangles[packed.emitters[e].slot].light_pdf_per_area = float(weights[e] / total / areas[e]);
  }
  return packed;
}

}  // namespace fovlab

#include "renderer/path_tracing/mesh_builder.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <glm/geometric.hpp>

namespace fovlab {

namespace {

constexpr float kTwoPi = 6.28318530717958647f;

}  // namespace

uint32_t add_material(PathScene& scene, const PathMaterial& material) {
  scene.materials.push_back(material);
  return uint32_t(scene.materials.size() - 1);
}

void add_triangle_facing(PathScene& scene, uint32_t material, const glm::vec3& a, const glm::vec3& b,
                         const glm::vec3& c, const glm::vec3& outward) {
  const bool flip = glm::dot(glm::cross(b - a, c - a), outward) < 0.0f;
  const auto first = uint32_t(scene.positions.size());
  scene.positions.push_back(a);
  scene.positions.push_back(flip ? c : b);
  scene.positions.push_back(flip ? b : c);
  scene.indices.insert(scene.indices.end(), {first, first + 1, first + 2});
  scene.material_per_triangle.push_back(material);
}

void add_quad_facing(PathScene& scene, uint32_t material, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                     const glm::vec3& d, const glm::vec3& outward) {
  add_triangle_facing(scene, material, a, b, c, outward);
  add_triangle_facing(scene, material, a, c, d, outward);
}

void add_box(PathScene& scene, uint32_t material, const glm::vec3& lo, const glm::vec3& hi) {
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      glm::vec3 corner[4];
      for (int k = 0; k < 4; ++k) {
        corner[k][axis] = side ? hi[axis] : lo[axis];
        corner[k][u] = (k == 1 || k == 2) ? hi[u] : lo[u];
        corner[k][v] = (k >= 2) ? hi[v] : lo[v];
      }
      glm::vec3 outward(0.0f);
      outward[axis] = side ? 1.0f : -1.0f;
      add_quad_facing(scene, material, corner[0], corner[1], corner[2], corner[3], outward);
    }
  }
}

void add_faceted_sphere(PathScene& scene, uint32_t material, const glm::vec3& centre, float radius, int rings,
                        int segments) {
  if (rings < 2 || segments < 3) throw std::invalid_argument("add_faceted_sphere: expected rings >= 2, segments >= 3");
  auto point = [&](int ring, int segment) {
    const float theta = std::numbers::pi_v<float> * float(ring) / float(rings);
    const float phi = kTwoPi * float(segment % segments) / float(segments);
    return centre +
           radius * glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
  };
  for (int ring = 0; ring < rings; ++ring) {
    for (int segment = 0; segment < segments; ++segment) {
      const glm::vec3 a = point(ring, segment), b = point(ring, segment + 1);
      const glm::vec3 c = point(ring + 1, segment + 1), d = point(ring + 1, segment);
      const glm::vec3 outward = 0.25f * (a + b + c + d) - centre;
      // At the top pole a == b, at the bottom one c == d: those bands are fans of one triangle each.
      if (ring > 0) add_triangle_facing(scene, material, a, b, c, outward);
      if (ring + 1 < rings) add_triangle_facing(scene, material, a, c, d, outward);
    }
  }
}

void add_prism(PathScene& scene, uint32_t material, const glm::vec3& base_centre, float radius, float height,
               int sides) {
  if (sides < 3) throw std::invalid_argument("add_prism: expected sides >= 3");
  const glm::vec3 up(0.0f, height, 0.0f);
  auto rim = [&](int k) {
    const float phi = kTwoPi * float(k % sides) / float(sides);
    return base_centre + radius * glm::vec3(std::cos(phi), 0.0f, std::sin(phi));
  };
  for (int k = 0; k < sides; ++k) {
    const glm::vec3 a = rim(k), b = rim(k + 1);
    const glm::vec3 outward = 0.5f * (a + b) - base_centre;
    add_quad_facing(scene, material, a, b, b + up, a + up, outward);
    add_triangle_facing(scene, material, base_centre, a, b, glm::vec3(0.0f, -1.0f, 0.0f));
    add_triangle_facing(scene, material, base_centre + up, a + up, b + up, glm::vec3(0.0f, 1.0f, 0.0f));
  }
}

}  // namespace fovlab

#include "renderer/path_tracing/ray_intersection.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "renderer/path_tracing/bvh.h"
#include "renderer/path_tracing/path_scene.h"

namespace fovlab {

namespace {

glm::vec3 vertex(const PathScene& scene, uint32_t triangle, int corner) {
  return scene.positions[scene.indices[3 * size_t(triangle) + size_t(corner)]];
}

// Entry distance of the ray into the box, or infinity when it misses it within (0, max_distance).
float box_entry(const glm::vec3& lo, const glm::vec3& hi, const glm::vec3& origin, const glm::vec3& inverse_direction,
                float max_distance) {
  const glm::vec3 t0 = (lo - origin) * inverse_direction;
  const glm::vec3 t1 = (hi - origin) * inverse_direction;
  const glm::vec3 near = glm::min(t0, t1), far = glm::max(t0, t1);
  const float enter = std::max(std::max(near.x, near.y), std::max(near.z, 0.0f));
  const float leave = std::min(std::min(far.x, far.y), std::min(far.z, max_distance));
  return enter <= leave ? enter : INFINITY;
}

// 1 / d with zero components replaced by a tiny value of the same sign, so slabs never see 0 * inf.
glm::vec3 safe_inverse(const glm::vec3& d) {
  glm::vec3 inverse;
  for (int i = 0; i < 3; ++i) inverse[i] = 1.0f / (std::fabs(d[i]) > 1e-20f ? d[i] : std::copysign(1e-20f, d[i]));
  return inverse;
}

void consider(const PathScene& scene, uint32_t triangle, const Ray& ray, std::optional<TriangleHit>& best,
              float& max_distance) {
  const std::optional<float> t = intersect_triangle(ray, vertex(scene, triangle, 0), vertex(scene, triangle, 1),
                                                    vertex(scene, triangle, 2), max_distance);
  if (t && (!best || *t < best->distance || (*t == best->distance && triangle < best->triangle))) {
    best = TriangleHit{*t, triangle};
    max_distance = std::nextafter(*t, INFINITY);  // keep equal distances for the tie rule
  }
}

}  // namespace

std::optional<float> intersect_triangle(const Ray& ray, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                                        float max_distance) {
  const glm::vec3 edge1 = b - a, edge2 = c - a;
  const glm::vec3 p = glm::cross(ray.direction, edge2);
  const float determinant = glm::dot(edge1, p);
  if (determinant == 0.0f) return std::nullopt;
  const float inverse = 1.0f / determinant;
  const glm::vec3 s = ray.origin - a;
  const float u = glm::dot(s, p) * inverse;
  if (u < 0.0f || u > 1.0f) return std::nullopt;
  const glm::vec3 q = glm::cross(s, edge1);
  const float v = glm::dot(ray.direction, q) * inverse;
  if (v < 0.0f || u + v > 1.0f) return std::nullopt;
  const float t = glm::dot(edge2, q) * inverse;
  if (!(t > 0.0f && t < max_distance)) return std::nullopt;
  return t;
}

std::optional<TriangleHit> intersect_brute_force(const PathScene& scene, const Ray& ray, float max_distance) {
  std::optional<TriangleHit> best;
  for (uint32_t t = 0; t < scene.triangle_count(); ++t) consider(scene, t, ray, best, max_distance);
  return best;
}

std::optional<TriangleHit> intersect_bvh(const PathScene& scene, const Bvh& bvh, const Ray& ray, float max_distance) {
  std::optional<TriangleHit> best;
  if (bvh.nodes.empty()) return best;
  const glm::vec3 inverse = safe_inverse(ray.direction);
  uint32_t stack[kBvhMaxDepth + 1];
  int size = 0;
  if (box_entry(bvh.nodes[0].bounds_min, bvh.nodes[0].bounds_max, ray.origin, inverse, max_distance) == INFINITY)
    return best;
  uint32_t node = 0;
  for (;;) {
    const BvhNode& n = bvh.nodes[node];
    if (n.triangle_count > 0) {
      for (uint32_t i = n.left_or_first; i < n.left_or_first + n.triangle_count; ++i)
        consider(scene, bvh.triangle_order[i], ray, best, max_distance);
    } else {
      const uint32_t left = n.left_or_first, right = left + 1;
      float near_t =
          box_entry(bvh.nodes[left].bounds_min, bvh.nodes[left].bounds_max, ray.origin, inverse, max_distance);
      float far_t =
          box_entry(bvh.nodes[right].bounds_min, bvh.nodes[right].bounds_max, ray.origin, inverse, max_distance);
      uint32_t near_node = left, far_node = right;
      if (far_t < near_t) {
        std::swap(near_t, far_t);
        std::swap(near_node, far_node);
      }
      if (near_t != INFINITY) {
        if (far_t != INFINITY) stack[size++] = far_node;
        node = near_node;
        continue;
      }
    }
    // Pop the next node that the ray can still reach (boxes are re-tested against the shrunk range).
    bool found = false;
    while (size > 0) {
      node = stack[--size];
      if (box_entry(bvh.nodes[node].bounds_min, bvh.nodes[node].bounds_max, ray.origin, inverse, max_distance) !=
          INFINITY) {
        found = true;
        break;
      }
    }
    if (!found) return best;
  }
}

}  // namespace fovlab

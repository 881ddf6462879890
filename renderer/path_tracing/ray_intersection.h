#pragma once
// Ray-triangle intersection on the CPU, by brute force and through a Bvh, with the same arithmetic
// as the shader (Moller-Trumbore, both faces; slab tests with the reciprocal direction). The tests
// check the BVH against brute force with it; tools may use it for picking.
#include <cstdint>
#include <optional>

#include <glm/vec3.hpp>

namespace fovlab {

struct Bvh;
struct PathScene;

struct Ray {
  glm::vec3 origin{0.0f};
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // need not be normalised; distances are in its units
};

struct TriangleHit {
  float distance = 0.0f;  // along the ray, in units of its direction's length
  uint32_t triangle = 0;  // scene triangle index
};

// Nearest hit with distance in (0, max_distance); ties go to the lower triangle index.
std::optional<TriangleHit> intersect_brute_force(const PathScene& scene, const Ray& ray, float max_distance);
std::optional<TriangleHit> intersect_bvh(const PathScene& scene, const Bvh& bvh, const Ray& ray, float max_distance);

// Distance to triangle (a, b, c) along the ray, when it is hit at a distance in (0, max_distance).
std::optional<float> intersect_triangle(const Ray& ray, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                                        float max_distance);

}  // namespace fovlab

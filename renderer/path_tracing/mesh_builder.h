#pragma once
// Appending simple closed shapes to a PathScene (the built-in courtyard and the tests use them).
// Every triangle is wound counter-clockwise seen from outside (its normal points out), which glass
// needs to tell entering from leaving.
#include <cstdint>

#include <glm/vec3.hpp>

#include "renderer/path_tracing/path_scene.h"

namespace fovlab {

// Returns the new material's index.
uint32_t add_material(PathScene& scene, const PathMaterial& material);

// One triangle, its winding flipped where needed so its normal has a positive dot with `outward`.
void add_triangle_facing(PathScene& scene, uint32_t material, const glm::vec3& a, const glm::vec3& b,
                         const glm::vec3& c, const glm::vec3& outward);
// A planar quad a-b-c-d (in order around it) as two triangles facing `outward`.
void add_quad_facing(PathScene& scene, uint32_t material, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                     const glm::vec3& d, const glm::vec3& outward);
// An axis-aligned box, 12 triangles.
void add_box(PathScene& scene, uint32_t material, const glm::vec3& min_corner, const glm::vec3& max_corner);
// A faceted sphere: `rings` bands from pole to pole (2: a bipyramid), `segments` around (>= 3).
void add_faceted_sphere(PathScene& scene, uint32_t material, const glm::vec3& centre, float radius, int rings,
                        int segments);
// A regular prism standing on its base: `sides` (>= 3) faces around, axis along +y.
void add_prism(PathScene& scene, uint32_t material, const glm::vec3& base_centre, float radius, float height,
               int sides);

}  // namespace fovlab

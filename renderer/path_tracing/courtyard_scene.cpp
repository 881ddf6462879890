#include "renderer/path_tracing/courtyard_scene.h"

#include <algorithm>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "renderer/path_tracing/mesh_builder.h"

namespace fovlab {

namespace {

constexpr float kHalfLength_m = 10.0f;    // courtyard along x
constexpr float kHalfWidth_m = 6.0f;      // courtyard along z, to the arcades
constexpr float kGalleryDepth_m = 3.0f;   // behind each arcade
constexpr float kWall_m = 0.3f;           // wall thickness
constexpr float kArcadeHeight_m = 4.0f;   // column height
constexpr float kGalleryHeight_m = 7.0f;  // gallery ceiling
constexpr float kWallHeight_m = 10.0f;    // top of the walls; open sky above the courtyard

PathMaterial lambertian(glm::vec3 albedo) { return {MaterialKind::lambertian, albedo, 1.5f}; }
PathMaterial glass(glm::vec3 tint) { return {MaterialKind::glass, tint, 1.5f}; }
PathMaterial emissive(glm::vec3 radiance) { return {MaterialKind::emissive, radiance, 1.0f}; }

// One long side (z_sign = +1 or -1): columns with haunch blocks under the wall above them, the wall
// up to the top, the gallery's back wall, its ceiling, and a lamp under the ceiling.
void add_arcade(PathScene& scene, float z_sign, uint32_t stone, uint32_t column, uint32_t ceiling, uint32_t lamp) {
  const float front = z_sign * kHalfWidth_m;
  const float back = z_sign * (kHalfWidth_m + kGalleryDepth_m);
  auto span_z = [&](float a, float b) { return glm::vec2(std::min(a, b), std::max(a, b)); };
  for (int i = -3; i <= 3; ++i) {
    const float x = 3.0f * float(i);
    const glm::vec2 z = span_z(front - 0.3f, front + 0.3f);
    add_box(scene, column, {x - 0.3f, 0.0f, z.x}, {x + 0.3f, kArcadeHeight_m, z.y});
    add_box(scene, stone, {x - 0.8f, kArcadeHeight_m - 0.5f, z.x}, {x + 0.8f, kArcadeHeight_m, z.y});  // haunches
  }
  const glm::vec2 wall = span_z(front - kWall_m, front + kWall_m);
  add_box(scene, stone, {-kHalfLength_m, kArcadeHeight_m, wall.x}, {kHalfLength_m, kWallHeight_m, wall.y});
  const glm::vec2 back_wall = span_z(back, back + z_sign * kWall_m);
  add_box(scene, stone, {-kHalfLength_m, 0.0f, back_wall.x}, {kHalfLength_m, kGalleryHeight_m, back_wall.y});
  const glm::vec2 roof = span_z(front, back);
  add_box(scene, ceiling, {-kHalfLength_m, kGalleryHeight_m, roof.x},
          {kHalfLength_m, kGalleryHeight_m + kWall_m, roof.y});
  const float lamp_z = 0.5f * (front + back);
  const float lamp_y = kGalleryHeight_m - 0.05f;
  add_quad_facing(scene, lamp, {-1.5f, lamp_y, lamp_z - 0.5f}, {1.5f, lamp_y, lamp_z - 0.5f},
                  {1.5f, lamp_y, lamp_z + 0.5f}, {-1.5f, lamp_y, lamp_z + 0.5f}, {0.0f, -1.0f, 0.0f});
}

}  // namespace

PathScene courtyard_scene() {
  PathScene scene;
  const uint32_t floor = add_material(scene, lambertian({0.55f, 0.50f, 0.42f}));
  const uint32_t stone = add_material(scene, lambertian({0.70f, 0.62f, 0.50f}));
  const uint32_t column = add_material(scene, lambertian({0.75f, 0.72f, 0.66f}));
  const uint32_t ceiling = add_material(scene, lambertian({0.50f, 0.30f, 0.25f}));
  const uint32_t pedestal = add_material(scene, lambertian({0.35f, 0.35f, 0.38f}));
  const uint32_t sun = add_material(scene, emissive({250.0f, 237.0f, 212.0f}));
  const uint32_t lamp = add_material(scene, emissive({6.0f, 4.5f, 3.0f}));
  const uint32_t red_glass = add_material(scene, glass({0.95f, 0.45f, 0.40f}));
  const uint32_t green_glass = add_material(scene, glass({0.50f, 0.92f, 0.55f}));
  const uint32_t blue_glass = add_material(scene, glass({0.45f, 0.62f, 0.95f}));

  const float outer_z = kHalfWidth_m + kGalleryDepth_m + kWall_m;
  add_box(scene, floor, {-kHalfLength_m, -kWall_m, -outer_z}, {kHalfLength_m, 0.0f, outer_z});
  for (float x_sign : {-1.0f, 1.0f}) {  // end walls
    const float x = x_sign * kHalfLength_m;
    add_box(scene, stone, {std::min(x, x + x_sign * kWall_m), 0.0f, -outer_z},
            {std::max(x, x + x_sign * kWall_m), kWallHeight_m, outer_z});
  }
  add_arcade(scene, 1.0f, stone, column, ceiling, lamp);
  add_arcade(scene, -1.0f, stone, column, ceiling, lamp);

  // The sun: a 6 m quad 47 m away, 72 degrees high above the far gallery, facing the courtyard.
  const glm::vec3 sun_centre(8.0f, 45.0f, -12.0f);
  const glm::vec3 towards = glm::normalize(glm::vec3(0.0f) - sun_centre);
  const glm::vec3 side_a = 3.0f * glm::normalize(glm::cross(towards, glm::vec3(0.0f, 1.0f, 0.0f)));
  const glm::vec3 side_b = 3.0f * glm::normalize(glm::cross(side_a, towards));
  add_quad_facing(scene, sun, sun_centre - side_a - side_b, sun_centre + side_a - side_b, sun_centre + side_a + side_b,
                  sun_centre - side_a + side_b, towards);

  // Three glass objects of different colours on pedestals (Polychronakis et al. 2021's three dragons).
  for (float x : {-4.0f, 0.0f, 4.0f}) add_box(scene, pedestal, {x - 0.5f, 0.0f, -0.5f}, {x + 0.5f, 0.9f, 0.5f});
  add_faceted_sphere(scene, red_glass, {-4.0f, 1.65f, 0.0f}, 0.75f, 7, 12);
  add_faceted_sphere(scene, green_glass, {0.0f, 1.85f, 0.0f}, 0.95f, 2, 6);  // a hexagonal bipyramid
  add_prism(scene, blue_glass, {4.0f, 0.9f, 0.0f}, 0.55f, 1.6f, 6);

  scene.sky_radiance = {0.35f, 0.45f, 0.60f};
  scene.camera.vertical_fov_deg = 60.0f;
  scene.camera.keyframes = {
      {0.0, {-8.0f, 1.7f, 4.5f}, {-2.0f, 1.2f, 0.0f}},
      {4.0, {-3.0f, 2.0f, 5.0f}, {-1.0f, 1.3f, 0.0f}},
      {8.0, {3.0f, 2.0f, 5.0f}, {1.0f, 1.3f, 0.0f}},
      {12.0, {8.0f, 1.7f, 4.5f}, {2.0f, 1.2f, 0.0f}},
  };
  return scene;
}

}  // namespace fovlab

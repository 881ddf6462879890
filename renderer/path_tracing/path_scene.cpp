#include "renderer/path_tracing/path_scene.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "core/input_error.h"
#include "core/number_text.h"

namespace fovlab {

namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string text(const glm::vec3& v) {
  return "(" + exact_number_text(v.x) + ", " + exact_number_text(v.y) + ", " + exact_number_text(v.z) + ")";
}

// Uniform Catmull-Rom segment between p1 and p2 at u in [0, 1].
glm::vec3 catmull_rom(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& p3, float u) {
  const float u2 = u * u, u3 = u2 * u;
  return 0.5f * (2.0f * p1 + (p2 - p0) * u + (2.0f * p0 - 5.0f * p1 + 4.0f * p2 - p3) * u2 +
                 (3.0f * p1 - p0 - 3.0f * p2 + p3) * u3);
}

void validate_camera(const CameraPath& camera) {
  if (camera.keyframes.empty()) throw InputError("scene camera: expected at least one keyframe");
  if (!(camera.vertical_fov_deg > 0.0f && camera.vertical_fov_deg < 180.0f))
    throw InputError("scene camera: vertical field of view " + exact_number_text(camera.vertical_fov_deg) +
                     " deg: expected more than 0 and less than 180");
  if (!finite(camera.up) || glm::length(camera.up) == 0.0f)
    throw InputError("scene camera: up " + text(camera.up) + ": expected a finite non-zero vector");
  for (size_t k = 0; k < camera.keyframes.size(); ++k) {
    const CameraKeyframe& key = camera.keyframes[k];
    const std::string where = "scene camera: keyframe " + std::to_string(k) + ": ";
    if (!std::isfinite(key.time_s) || !finite(key.eye) || !finite(key.target))
      throw InputError(where + "expected a finite time, eye and target");
    if (key.eye == key.target) throw InputError(where + "eye equals target: expected distinct points");
    if (k > 0 && !(key.time_s > camera.keyframes[k - 1].time_s))
      throw InputError(where + "time " + exact_number_text(key.time_s) +
                       " s: expected more than the previous keyframe's");
  }
}

}  // namespace

CameraPose camera_pose_at(const CameraPath& path, double time_s) {
  const std::vector<CameraKeyframe>& keys = path.keyframes;
  if (keys.empty()) return {};
  if (!(time_s > keys.front().time_s)) return {keys.front().eye, keys.front().target};
  if (!(time_s < keys.back().time_s)) return {keys.back().eye, keys.back().target};
  size_t i = 0;
  while (keys[i + 1].time_s <= time_s) ++i;
  const size_t i0 = i == 0 ? 0 : i - 1, i3 = std::min(i + 2, keys.size() - 1);
  const float u = float((time_s - keys[i].time_s) / (keys[i + 1].time_s - keys[i].time_s));
  return {catmull_rom(keys[i0].eye, keys[i].eye, keys[i + 1].eye, keys[i3].eye, u),
          catmull_rom(keys[i0].target, keys[i].target, keys[i + 1].target, keys[i3].target, u)};
}

void validate(const PathScene& scene) {
  if (scene.indices.empty()) throw InputError("scene: no triangles: expected at least one");
  if (scene.indices.size() % 3 != 0)
    throw InputError("scene: " + std::to_string(scene.indices.size()) + " indices: expected 3 per triangle");
  const size_t triangles = scene.triangle_count();
  if (scene.material_per_triangle.size() != triangles)
    throw InputError("scene: " + std::to_string(scene.material_per_triangle.size()) + " triangle materials: expected " +
                     std::to_string(triangles) + ", one per triangle");
  if (scene.materials.empty()) throw InputError("scene: no materials: expected at least one");
  for (size_t p = 0; p < scene.positions.size(); ++p)
    if (!finite(scene.positions[p]))
      throw InputError("scene: position " + std::to_string(p) + ": expected finite coordinates");
  for (size_t t = 0; t < triangles; ++t) {
    for (int c = 0; c < 3; ++c) {
      const uint32_t index = scene.indices[3 * t + size_t(c)];
      if (index >= scene.positions.size())
        throw InputError("scene: triangle " + std::to_string(t) + ": vertex index " + std::to_string(index) +
                         ": expected less than " + std::to_string(scene.positions.size()));
    }
    if (scene.material_per_triangle[t] >= scene.materials.size())
      throw InputError("scene: triangle " + std::to_string(t) + ": material " +
                       std::to_string(scene.material_per_triangle[t]) + ": expected less than " +
                       std::to_string(scene.materials.size()));
  }
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    const PathMaterial& material = scene.materials[m];
    const std::string where = "scene: material " + std::to_string(m) + ": ";
    if (material.kind != MaterialKind::lambertian && material.kind != MaterialKind::glass &&
        material.kind != MaterialKind::emissive)
      throw InputError(where + "expected the kind lambertian, glass or emissive");
    if (!finite(material.colour) || material.colour.x < 0.0f || material.colour.y < 0.0f || material.colour.z < 0.0f)
      throw InputError(where + "colour " + text(material.colour) + ": expected finite non-negative values");
    if (material.kind != MaterialKind::emissive &&
        std::max({material.colour.x, material.colour.y, material.colour.z}) > 1.0f)
      throw InputError(where + "colour " + text(material.colour) + ": expected an albedo or tint of at most 1");
    if (material.kind == MaterialKind::glass &&
        !(std::isfinite(material.index_of_refraction) && material.index_of_refraction >= 1.0f))
      throw InputError(where + "index of refraction " + exact_number_text(material.index_of_refraction) +
                       ": expected a finite value of at least 1");
  }
  if (!finite(scene.sky_radiance) || scene.sky_radiance.x < 0.0f || scene.sky_radiance.y < 0.0f ||
      scene.sky_radiance.z < 0.0f)
    throw InputError("scene: sky radiance " + text(scene.sky_radiance) + ": expected finite non-negative values");
  validate_camera(scene.camera);
}

}  // namespace fovlab

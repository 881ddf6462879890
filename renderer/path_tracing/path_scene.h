#pragma once
// A scene for the path tracer (Polychronakis et al. 2021, sections 3.1 and 4): world-space triangles, one material
// per triangle, a uniform sky and a keyframed camera path. docs/path-tracing.md.
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace fovlab {

enum class MaterialKind : uint32_t { lambertian = 0, glass = 1, emissive = 2 };

struct PathMaterial {
  MaterialKind kind = MaterialKind::lambertian;
  // lambertian: albedo in [0, 1]; glass: the tint, a transmittance applied on every refraction
  // through the surface (a ray through a closed object is tinted twice); emissive: the radiance it
  // emits from both faces (it reflects nothing).
  glm::vec3 colour{0.5f};
  float index_of_refraction = 1.5f;  // glass only; >= 1, outside is vacuum (1)
};

struct CameraKeyframe {
  double time_s = 0.0;
  glm::vec3 eye{0.0f};
  glm::vec3 target{0.0f, 0.0f, -1.0f};
};

// Eye and look-at target interpolated by a Catmull-Rom spline through the keyframes (times
// strictly increasing); held at the first keyframe before it and at the last after it.
struct CameraPath {
  std::vector<CameraKeyframe> keyframes;
  float vertical_fov_deg = 60.0f;
  glm::vec3 up{0.0f, 1.0f, 0.0f};
};

struct CameraPose {
  glm::vec3 eye{0.0f};
  glm::vec3 target{0.0f, 0.0f, -1.0f};
};

CameraPose camera_pose_at(const CameraPath& path, double time_s);

struct PathScene {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;                // 3 per triangle, into positions
  std::vector<uint32_t> material_per_triangle;  // one per triangle, into materials
  std::vector<PathMaterial> materials;
  CameraPath camera;
  glm::vec3 sky_radiance{0.0f};  // radiance of every ray that leaves the scene

  size_t triangle_count() const { return indices.size() / 3; }
};

// Throws InputError naming the first thing that is wrong: no triangles, an index or material out of
// range, a non-finite position, a negative or non-finite colour, an index of refraction below 1, a
// camera path without keyframes, with non-increasing times, non-finite values, an eye on its
// target, or a field of view outside (0, 180) degrees.
void validate(const PathScene& scene);

}  // namespace fovlab

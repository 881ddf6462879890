#pragma once
// A PathScene from a Wavefront OBJ file and its MTL materials (tinyobjloader), e.g. Sponza with
// glass dragons. docs/path-tracing.md has the material mapping and what is ignored.
#include <cstddef>
#include <filesystem>
#include <string>

#include "renderer/path_tracing/path_scene.h"

namespace fovlab {

struct ObjLoadReport {
  size_t triangles = 0;                     // in the scene (polygons are split into fans)
  size_t dropped_degenerate_triangles = 0;  // zero-area triangles left out
  size_t triangles_without_material = 0;    // no usemtl, or an unknown name: the default grey Lambertian
  std::string summary() const;              // one line, e.g. for a command to print
};

// Materials: Ke > 0 -> emissive (radiance Ke); else d < 1 or illum 4, 6 or 7 -> glass (tint Tf, or
// white when Tf is 0; IOR Ni, or 1.5 when Ni <= 1); else Lambertian (Kd clamped to [0, 1]).
// Textures and normals are ignored. The camera path frames the bounding box (a slow orbit over
// 10 s); the sky is a soft blue-white. Throws InputError "<file>:<line>: expected ..." for a missing
// or unreadable file, a missing material library, a vertex that is not three finite numbers, a face
// index out of range; "<file>: ..." when no triangle is left. Zero-area triangles are dropped and
// counted in the report (never silently: a caller prints report.summary()).
PathScene load_obj_scene(const std::filesystem::path& obj_file, ObjLoadReport* report = nullptr);

}  // namespace fovlab

#pragma once
// A PathScene from a Wavefront OBJ file and its MTL materials (tinyobjloader), e.g. Sponza with
// glass dragons. docs/path-tracing.md has the material mapping and what is ignored.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
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
// Textures, normals and skin weights (`vw`) are ignored. The camera path frames the bounding box (a slow orbit over
// 10 s); the sky is a soft blue-white. Throws InputError "<file>:<line>: expected ..." for a missing
// or unreadable file, a missing material library, a vertex that is not three finite numbers, a face
// index out of range; "<file>: ..." when no triangle is left. Zero-area triangles are dropped and
// counted in the report (never silently: a caller prints report.summary()).
// The OBJ must be a regular file of at most kMaxObjBytes, each MTL library one of at most
// kMaxMtlBytes (core/input_file.h: "<file>: not a regular file (a directory): expected an OBJ
// mesh"). A UTF-8 byte-order mark at the start of either is ignored.
constexpr uint64_t kMaxObjBytes = uint64_t(512) << 20;  // 512 MiB: Sponza is 20 MB
constexpr uint64_t kMaxMtlBytes = uint64_t(64) << 20;   // 64 MiB: real libraries are some KiB
PathScene load_obj_scene(const std::filesystem::path& obj_file, ObjLoadReport* report = nullptr);

// The text of the material library an `mtllib` line names (as written), or an InputError saying why
// there is none.
using MtlLibraryReader = std::function<std::string(const std::string& library)>;

// load_obj_scene on text already read: `name` (normally the path) starts the error messages, and
// read_library gives the MTL libraries. An InputError from read_library is reported as
// "<name>:<line>: material library: <its message>". For the fuzzer, and for OBJ text from elsewhere.
PathScene parse_obj_scene(const std::string& obj_text, const std::string& name, const MtlLibraryReader& read_library,
                          ObjLoadReport* report = nullptr);

}  // namespace fovlab

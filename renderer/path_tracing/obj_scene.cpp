#include "renderer/path_tracing/obj_scene.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string_view>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "core/input_file.h"
#include "core/input_error.h"

namespace fovlab {

namespace {

constexpr float kDefaultFovDeg = 60.0f;
const glm::vec3 kDefaultSkyRadiance{0.6f, 0.7f, 0.85f};
const PathMaterial kDefaultMaterial{MaterialKind::lambertian, glm::vec3(0.5f), 1.5f};
// A triangle whose height is below this fraction of its longest edge has no area at float precision.
constexpr double kDegenerateRatio = 1e-7;

std::string_view trim(std::string_view s) {
  const size_t begin = s.find_first_not_of(" \t\r");
  if (begin == std::string_view::npos) return {};
  return s.substr(begin, s.find_last_not_of(" \t\r") - begin + 1);
}

// What the loader needs from the text before tinyobjloader parses it (which reads a bad number
// as 0 and gives no line numbers): every vertex line checked, the line of each face, the
// material libraries.
struct ObjPrescan {
  std::vector<int> face_lines;
  std::vector<std::pair<std::string, int>> material_libraries;  // name, line
  // Where the skin-weight lines (`vw`, a tinyobjloader extension fovlab ignores) start: tinyobjloader
  // converts their joint ids to int unchecked (undefined behaviour for 1e30; found by fuzzing), so
  // they are made comments before it sees them.
  std::vector<size_t> skin_weight_lines;
};

ObjPrescan prescan(const std::string& text, const std::string& file) {
  ObjPrescan result;
  int line_number = 0;
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    ++line_number;
    const std::string_view line = trim(std::string_view(text).substr(start, end - start));
    start = end + 1;
    if (line.size() > 2 && line[0] == 'v' && (line[1] == ' ' || line[1] == '\t')) {
      std::string_view rest = line.substr(2);
      for (int c = 0; c < 3; ++c) {
        rest = trim(rest);
        const size_t token_end = std::min(rest.find_first_of(" \t"), rest.size());
        float value = 0.0f;
        const auto [ptr, error] = std::from_chars(rest.data(), rest.data() + token_end, value);
        if (error != std::errc() || ptr != rest.data() + token_end || !std::isfinite(value))
          throw InputError(file + ":" + std::to_string(line_number) + ": expected three finite vertex coordinates");
        rest = rest.substr(token_end);
      }
    } else if (line.size() > 3 && line[0] == 'v' && line[1] == 'w' && (line[2] == ' ' || line[2] == '\t')) {
      result.skin_weight_lines.push_back(static_cast<size_t>(line.data() - text.data()));
    } else if (line.size() > 2 && line[0] == 'f' && (line[1] == ' ' || line[1] == '\t')) {
      result.face_lines.push_back(line_number);
    } else if (line.rfind("mtllib", 0) == 0 && line.size() > 7) {
      result.material_libraries.emplace_back(std::string(trim(line.substr(6))), line_number);
    }
    if (end == text.size()) break;
  }
  return result;
}

// The text without a UTF-8 byte-order mark at its start (tinyobjloader would take the mark for part
// of the first line's keyword and skip that line: a vertex lost, every index after it shifted).
std::string without_byte_order_mark(const std::string& text) {
  return text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? text.substr(3) : text;
}

// tinyobjloader's messages, a line each, as one line.
std::string one_line(const std::string& text) {
  std::string out;
  for (const char c : trim(text)) out += (c == '\n' || c == '\r') ? ' ' : c;
  return out;
}

bool finite3(const float* v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

PathMaterial convert_material(const tinyobj::material_t& m, const std::string& where) {
  if (!finite3(m.diffuse) || !finite3(m.emission) || !finite3(m.transmittance) || !std::isfinite(m.ior) ||
      !std::isfinite(m.dissolve))
    throw InputError(where + ": material " + m.name + ": expected finite Kd, Ke, Tf, Ni and d");
  const glm::vec3 emission(m.emission[0], m.emission[1], m.emission[2]);
  if (std::max({emission.x, emission.y, emission.z}) > 0.0f)
    return {MaterialKind::emissive, glm::max(emission, glm::vec3(0.0f)), 1.0f};
  if (m.dissolve < 1.0f || m.illum == 4 || m.illum == 6 || m.illum == 7) {
    glm::vec3 tint = glm::clamp(glm::vec3(m.transmittance[0], m.transmittance[1], m.transmittance[2]), 0.0f, 1.0f);
    if (std::max({tint.x, tint.y, tint.z}) == 0.0f) tint = glm::vec3(1.0f);
    return {MaterialKind::glass, tint, m.ior > 1.0f ? m.ior : 1.5f};
  }
  return {MaterialKind::lambertian, glm::clamp(glm::vec3(m.diffuse[0], m.diffuse[1], m.diffuse[2]), 0.0f, 1.0f), 1.5f};
}

// A slow orbit of +-15 degrees over 10 s around the bounding box, at a distance that fits it in view.
CameraPath framing_camera(const glm::vec3& lo, const glm::vec3& hi) {
  const glm::vec3 centre = 0.5f * (lo + hi);
  const float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
  const float distance = radius / std::sin(glm::radians(kDefaultFovDeg) * 0.5f);
  CameraPath camera;
  camera.vertical_fov_deg = kDefaultFovDeg;
  for (int k = 0; k < 3; ++k) {
    const float azimuth = glm::radians(-15.0f + 15.0f * float(k));
    const glm::vec3 direction = glm::normalize(glm::vec3(std::sin(azimuth), 0.35f, std::cos(azimuth)));
    camera.keyframes.push_back({5.0 * k, centre + distance * direction, centre});
  }
  return camera;
}

}  // namespace

std::string ObjLoadReport::summary() const {
  return std::to_string(triangles) + " triangles, " + std::to_string(dropped_degenerate_triangles) +
         " zero-area triangles dropped, " + std::to_string(triangles_without_material) +
         " without a material (grey Lambertian)";
}

PathScene load_obj_scene(const std::filesystem::path& obj_file, ObjLoadReport* report) {
  const std::string text = read_input_file(obj_file, "an OBJ mesh", kMaxObjBytes);
  const auto read_library = [&](const std::string& library) {
    return read_input_file(obj_file.parent_path() / library, "an MTL material library", kMaxMtlBytes);
  };
  return parse_obj_scene(text, obj_file.string(), read_library, report);
}

PathScene parse_obj_scene(const std::string& obj_text, const std::string& name, const MtlLibraryReader& read_library,
                          ObjLoadReport* report) {
  const std::string& file = name;
  std::string text = without_byte_order_mark(obj_text);
  const ObjPrescan scan = prescan(text, file);
  for (const size_t line_start : scan.skin_weight_lines) text[line_start] = '#';
  std::string mtl_text;
  for (const auto& [library, line] : scan.material_libraries) {
    try {
      mtl_text += without_byte_order_mark(read_library(library)) + "\n";
    } catch (const InputError& error) {
      throw InputError(file + ":" + std::to_string(line) + ": material library: " + error.what());
    }
  }

  tinyobj::ObjReaderConfig config;
  config.triangulate = false;  // fans below, so faces keep their lines
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromString(text, mtl_text, config))
    throw InputError(file + ": expected a Wavefront OBJ file: " + one_line(reader.Error()));

  PathScene scene;
  for (const tinyobj::material_t& material : reader.GetMaterials())
    scene.materials.push_back(convert_material(material, file));
  const auto default_material = uint32_t(scene.materials.size());
  scene.materials.push_back(kDefaultMaterial);

  const std::vector<float>& vertices = reader.GetAttrib().vertices;
  const size_t vertex_count = vertices.size() / 3;
  for (size_t v = 0; v < vertex_count; ++v)
    scene.positions.emplace_back(vertices[3 * v], vertices[3 * v + 1], vertices[3 * v + 2]);

  size_t face_total = 0;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) face_total += shape.mesh.num_face_vertices.size();
  const bool lines_known = face_total == scan.face_lines.size();
  ObjLoadReport counts;
  size_t face = 0;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    size_t offset = 0;
    for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f, ++face) {
      const size_t corners = shape.mesh.num_face_vertices[f];
      const std::string where =
          lines_known ? file + ":" + std::to_string(scan.face_lines[face]) : file + ": face " + std::to_string(face);
      std::vector<uint32_t> polygon;
      for (size_t c = 0; c < corners; ++c) {
        const int index = shape.mesh.indices[offset + c].vertex_index;
        if (index < 0 || size_t(index) >= vertex_count)
          throw InputError(where + ": vertex index out of range: expected 1 to " + std::to_string(vertex_count) +
                           " (or a valid negative index)");
        polygon.push_back(uint32_t(index));
      }
      offset += corners;
      const int material_id = f < shape.mesh.material_ids.size() ? shape.mesh.material_ids[f] : -1;
      const bool has_material = material_id >= 0 && size_t(material_id) < default_material;
      for (size_t c = 1; c + 1 < corners; ++c) {
        const glm::dvec3 a(scene.positions[polygon[0]]), b(scene.positions[polygon[c]]),
            d(scene.positions[polygon[c + 1]]);
        const double longest2 = std::max({glm::dot(b - a, b - a), glm::dot(d - b, d - b), glm::dot(a - d, a - d)});
        const double doubled_area = glm::length(glm::cross(b - a, d - a));
        if (!(doubled_area > kDegenerateRatio * longest2)) {  // height < ratio x longest edge
          ++counts.dropped_degenerate_triangles;
          continue;
        }
        scene.indices.insert(scene.indices.end(), {polygon[0], polygon[c], polygon[c + 1]});
        scene.material_per_triangle.push_back(has_material ? uint32_t(material_id) : default_material);
        if (!has_material) ++counts.triangles_without_material;
      }
    }
  }
  counts.triangles = scene.triangle_count();
  if (scene.indices.empty())
    throw InputError(file + ": no triangles (" + std::to_string(counts.dropped_degenerate_triangles) +
                     " of zero area dropped): expected at least one face of non-zero area");

  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (uint32_t index : scene.indices) {
    lo = glm::min(lo, scene.positions[index]);
    hi = glm::max(hi, scene.positions[index]);
  }
  scene.camera = framing_camera(lo, hi);
  scene.sky_radiance = kDefaultSkyRadiance;
  try {
    validate(scene);
  } catch (const InputError& error) {
    throw InputError(file + ": " + error.what());
  }
  if (report) *report = counts;
  return scene;
}

}  // namespace fovlab

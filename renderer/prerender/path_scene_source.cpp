#include "renderer/prerender/path_scene_source.h"

#include <string_view>

#include "core/content_hash.h"
#include "core/input_error.h"
#include "renderer/path_tracing/courtyard_scene.h"
#include "renderer/path_tracing/obj_scene.h"

namespace fovlab {

namespace {

bool ends_with_obj(const std::string& scene) {
  if (scene.size() < 4) return false;
  std::string extension = scene.substr(scene.size() - 4);
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".obj";
}

template <typename T>
void add_values(ContentHash& hash, const std::vector<T>& values) {
  hash.add(std::string_view(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)));
}

template <typename T>
void add_value(ContentHash& hash, const T& value) {
  hash.add(std::string_view(reinterpret_cast<const char*>(&value), sizeof(T)));
}

// Every field the renderer reads, byte for byte (floats as stored: the same scene on another
// platform with the same float layout hashes the same).
std::string scene_hash(const PathScene& scene) {
  ContentHash hash;
  hash.add("path-scene-v1");
  add_values(hash, scene.positions);
  add_values(hash, scene.indices);
  add_values(hash, scene.material_per_triangle);
  for (const PathMaterial& material : scene.materials) {
    add_value(hash, static_cast<uint32_t>(material.kind));
    add_value(hash, material.colour);
    add_value(hash, material.index_of_refraction);
  }
  for (const CameraKeyframe& key : scene.camera.keyframes) {
    add_value(hash, key.time_s);
    add_value(hash, key.eye);
    add_value(hash, key.target);
  }
  add_value(hash, scene.camera.vertical_fov_deg);
  add_value(hash, scene.camera.up);
  add_value(hash, scene.sky_radiance);
  return hash.hex();
}

}  // namespace

std::string known_path_scenes() { return "courtyard"; }

bool is_path_scene_name(const std::string& scene) { return scene == "courtyard" || ends_with_obj(scene); }

LoadedPathScene load_path_scene(const std::string& scene) {
  LoadedPathScene loaded;
  if (scene == "courtyard") {
    loaded.scene = courtyard_scene();
  } else if (ends_with_obj(scene)) {
    ObjLoadReport report;
    loaded.scene = load_obj_scene(scene, &report);
    loaded.load_note = report.summary();
  } else {
    throw InputError("path-traced scene \"" + scene + "\": expected " + known_path_scenes() + " or a .obj file");
  }
  validate(loaded.scene);
  loaded.content_hash = scene_hash(loaded.scene);
  return loaded;
}

}  // namespace fovlab

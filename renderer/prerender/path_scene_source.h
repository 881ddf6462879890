#pragma once
// Which path-traced scene a stimulus names: the built-in "courtyard", or a Wavefront OBJ file
// (a path ending in .obj; relative paths from the working directory). docs/foveated-path-tracing.md.
#include <string>

#include "renderer/path_tracing/path_scene.h"

namespace fovlab {

// "courtyard".
std::string known_path_scenes();
// Whether the name could be a path-traced scene: a built-in name or a path ending in .obj (the file
// is only read by load_path_scene).
bool is_path_scene_name(const std::string& scene);

struct LoadedPathScene {
  PathScene scene;
  std::string content_hash;  // of everything the renderer reads (geometry, materials, camera, sky)
  std::string load_note;     // OBJ: the loader's report (dropped triangles...); empty for built-ins
};

// InputError naming the scene when it is neither a built-in nor a readable, valid OBJ.
LoadedPathScene load_path_scene(const std::string& scene);

}  // namespace fovlab

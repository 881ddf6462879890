#pragma once
// Finding and reading a scene: a built-in name (a file in stimuli/scenes/) or a path to a .glsl file.
#include <filesystem>
#include <string>
#include <vector>

namespace fovlab {

struct SceneSource {
  std::string name;             // file stem, e.g. "primitives"
  std::filesystem::path path;   // the file read, as shown in error messages
  std::string text;
};

// The folder of built-in scenes: $FOVLAB_SCENES_DIR if set, else the source tree's stimuli/scenes.
std::filesystem::path builtin_scenes_directory();

// Names of the built-in scenes, sorted.
std::vector<std::string> builtin_scene_names();

// `name_or_file` is a built-in name ("columns") or a path ("my/scene.glsl"). Throws InputError
// naming the scene and what was expected when it cannot be found or read.
SceneSource load_scene(const std::string& name_or_file);

}  // namespace fovlab

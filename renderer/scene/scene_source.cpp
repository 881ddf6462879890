#include "renderer/scene/scene_source.h"

#include <algorithm>
#include <cstdlib>

#include "core/data_folders.h"
#include "core/input_file.h"
#include "core/input_error.h"

namespace fovlab {

std::filesystem::path builtin_scenes_directory() { return stimuli_subdirectory("FOVLAB_SCENES_DIR", "scenes"); }

std::vector<std::string> builtin_scene_names() {
  std::vector<std::string> names;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(builtin_scenes_directory(), error)) {
    if (entry.path().extension() == ".glsl") names.push_back(entry.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

namespace {
bool is_scene_path(const std::string& name_or_file) {
  return name_or_file.find('/') != std::string::npos || std::filesystem::path(name_or_file).extension() == ".glsl";
}
}  // namespace

std::string scene_name(const std::string& name_or_file) {
  return is_scene_path(name_or_file) ? std::filesystem::path(name_or_file).stem().string() : name_or_file;
}

SceneSource load_scene(const std::string& name_or_file) {
  const bool is_path = is_scene_path(name_or_file);
  SceneSource scene;
  if (is_path) {
    scene.path = name_or_file;
  } else {
    scene.path = builtin_scenes_directory() / (name_or_file + ".glsl");
    if (!std::filesystem::is_regular_file(scene.path)) {
      std::string known;
      for (const std::string& name : builtin_scene_names()) known += (known.empty() ? "" : ", ") + name;
      throw InputError("--scene " + name_or_file + ": unknown scene; expected one of " + known +
                       " or a path to a .glsl file");
    }
  }
  scene.name = scene_name(name_or_file);
  scene.text = read_input_file(scene.path, "a GLSL scene file (docs/scenes.md)", kMaxSceneBytes);
  if (scene.text.compare(0, 3, "\xEF\xBB\xBF") == 0) scene.text.erase(0, 3);  // a byte-order mark
  return scene;
}

}  // namespace fovlab

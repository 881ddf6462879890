#pragma once
// Finding and reading a scene: a built-in name (a file in stimuli/scenes/) or a path to a .glsl file.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace fovlab {

struct SceneSource {
  std::string name;            // file stem, e.g. "primitives"
  std::filesystem::path path;  // the file read, as shown in error messages
  std::string text;
};

// The folder of built-in scenes: $FOVLAB_SCENES_DIR if set, else stimuli/scenes beside the program
// (core/data_folders.h).
std::filesystem::path builtin_scenes_directory();

// Names of the built-in scenes, sorted.
std::vector<std::string> builtin_scene_names();

// A scene file must be a regular file (not a directory, device or FIFO) of at most this size; the
// built-in scenes are about 10 KiB.
constexpr uint64_t kMaxSceneBytes = uint64_t(4) << 20;  // 4 MiB

// The name a scene goes by (SceneSource::name), without reading it: a built-in name as given, a
// path's file stem ("my/scene.glsl": "scene").
std::string scene_name(const std::string& name_or_file);

// `name_or_file` is a built-in name ("columns") or a path ("my/scene.glsl"). Throws InputError
// naming the scene and what was expected when it cannot be found or read. A UTF-8 byte-order mark
// at the start of the file is left out of `text` (GLSL has no place for one).
SceneSource load_scene(const std::string& name_or_file);

}  // namespace fovlab

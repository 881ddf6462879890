#pragma once
// The scenes a config may name, by the kind of scene a method renders. The study library knows no
// renderer: whoever parses a config passes the catalog in (renderer_scene_catalog() in
// protocols/stimuli/stimulus_settings.h makes the renderer's).
#include <string>
#include <vector>

namespace fovlab {

struct SceneCatalog {
  std::vector<std::string> signed_distance_names;  // built-in SDF scenes; any other name is a file path
  std::vector<std::string> path_traced_names;      // built-in path-traced scenes
  std::string path_traced_file_extension;          // the only files a path-traced scene may be (".obj")
  bool check_files = true;                         // scene files must exist (false: taken as written)
  std::vector<std::string> volume_names;           // built-in volume scenes
  std::string volume_file_extension;               // the only files a volume scene may be (".toml")
};

}  // namespace fovlab

#pragma once
// Run-time compilation of a scene together with a renderer shader (glslang library), cached on disk
// by content hash: an unchanged scene is never compiled twice, a new scene needs no rebuild.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "renderer/scene/scene_source.h"
#include "renderer/shaders/embedded_shaders.h"

namespace fovlab {

struct CompiledShader {
  std::vector<uint32_t> spirv;
  bool from_cache = false;
  std::filesystem::path cache_file;
};

// The renderer shader that consumes a scene: its text follows the scene's in the compiled unit. It
// may #include the headers given (shaders::shared_headers), and nothing else.
struct SceneConsumerShader {
  std::string_view name;  // e.g. "sphere_trace.comp.glsl", shown in messages about it
  std::string_view source;
  std::span<const shaders::ShaderHeader> headers;
};

// $FOVLAB_SHADER_CACHE, else $XDG_CACHE_HOME/fovlab/spirv, else ~/.cache/fovlab/spirv.
std::filesystem::path shader_cache_directory();

// Compiles "#version 460" + scene + consumer as one compute shader for Vulkan 1.1, or loads the
// cached SPIR-V of the same text. A GLSL error in the scene throws InputError as
// "path/scene.glsl:LINE: message"; an error the consumer reports (usually a missing or misdeclared
// scene function) names the scene file and the scene interface.
CompiledShader compile_scene_shader(const SceneSource& scene, const SceneConsumerShader& consumer);

// The cache key of that SPIR-V (hex): the glslang version, the scene's text, the consumer's and every
// header it may include, names and texts, so that no edit meets a stale cached module.
std::string scene_shader_cache_key(const SceneSource& scene, const SceneConsumerShader& consumer);

}  // namespace fovlab

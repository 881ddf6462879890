#include "renderer/scene/scene_compiler.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <cstdlib>
#include <cstring>
#include <mutex>
#include <optional>
#include <regex>
#include <sstream>
#include <string>

#include "core/atomic_file.h"
#include "core/output_guard.h"
#include "core/content_hash.h"
#include "core/input_error.h"
#include "core/input_file.h"
#include "renderer/scene/shader_includes.h"

namespace fovlab {

namespace {

constexpr std::string_view kVersionLine = "#version 460\n";
constexpr std::string_view kCacheFormat = "fovlab-spirv-cache-1";
constexpr uint32_t kSpirvMagic = 0x07230203;

void initialise_glslang_once() {
  static std::once_flag once;
  std::call_once(once, [] {
    glslang::InitializeProcess();
    std::atexit([] { glslang::FinalizeProcess(); });
  });
}

// glslang reports "ERROR: <string name>:<line>: <message>", the name quoted or not.
struct CompileMessage {
  std::string source_name;
  int line = 0;
  std::string text;
};

std::vector<CompileMessage> parse_errors(const std::string& log) {
  static const std::regex pattern(R"re(^ERROR: "?([^":]*)"?:(\d+): (.*)$)re");
  std::vector<CompileMessage> messages;
  std::istringstream lines(log);
  std::string line;
  while (std::getline(lines, line)) {
    std::smatch match;
    if (std::regex_match(line, match, pattern)) messages.push_back({match[1], std::stoi(match[2]), match[3]});
  }
  return messages;
}

std::string first_error_line(const std::string& log) {
  std::istringstream lines(log);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("ERROR:", 0) == 0) return line.substr(7);
  }
  return log.empty() ? std::string("unknown glslang error") : log;
}

[[noreturn]] void throw_compile_error(const SceneSource& scene, const SceneConsumerShader& consumer,
                                      const std::string& log) {
  const std::string scene_label = scene.path.string();
  for (const CompileMessage& message : parse_errors(log)) {
    if (message.source_name == scene_label) {
      throw InputError(scene_label + ":" + std::to_string(message.line) + ": " + message.text);
    }
  }
  for (const CompileMessage& message : parse_errors(log)) {
    if (message.source_name == consumer.name) {
      throw InputError(scene_label + ": does not fit the scene interface (docs/scenes.md): " + message.text + " [" +
                       std::string(consumer.name) + ":" + std::to_string(message.line) + "]");
    }
  }
  throw InputError(scene_label + ": " + first_error_line(log));
}

std::vector<uint32_t> compile_glsl(const SceneSource& scene, const SceneConsumerShader& consumer) {
  initialise_glslang_once();
  const std::string scene_label = scene.path.string();
  const char* texts[] = {kVersionLine.data(), scene.text.c_str(), consumer.source.data()};
  const int lengths[] = {static_cast<int>(kVersionLine.size()), static_cast<int>(scene.text.size()),
                         static_cast<int>(consumer.source.size())};
  const std::string consumer_name(consumer.name);
  const char* names[] = {"fovlab-prelude", scene_label.c_str(), consumer_name.c_str()};

  glslang::TShader shader(EShLangCompute);
  shader.setStringsWithLengthsAndNames(texts, lengths, names, 3);
  shader.setEnvInput(glslang::EShSourceGlsl, EShLangCompute, glslang::EShClientVulkan, 100);
  shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_1);
  shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_3);
  const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);
  SharedHeaderIncluder includer(consumer.headers);
  if (!shader.parse(GetDefaultResources(), 460, ENoProfile, false, false, messages, includer)) {
    throw_compile_error(scene, consumer, shader.getInfoLog());
  }
  glslang::TProgram program;
  program.addShader(&shader);
  if (!program.link(messages)) throw_compile_error(scene, consumer, program.getInfoLog());

  std::vector<uint32_t> spirv;
  glslang::SpvOptions options;
  options.disableOptimizer = false;
  glslang::GlslangToSpv(*program.getIntermediate(EShLangCompute), spirv, &options);
  return spirv;
}

// A cached module is at most 64 MiB (a scene's is some hundred KiB); a file that is not a regular file
// of at most that (a FIFO, a device, a link to one) is not read: the scene is compiled again.
constexpr uint64_t kMaxCachedSpirvBytes = uint64_t(64) << 20;

std::vector<uint32_t> read_cached_spirv(const std::filesystem::path& file) {
  const std::optional<std::string> bytes = read_file_if_regular(file, kMaxCachedSpirvBytes);
  if (!bytes || bytes->size() < 20 || bytes->size() % 4 != 0) return {};
  std::vector<uint32_t> words(bytes->size() / 4);
  std::memcpy(words.data(), bytes->data(), bytes->size());
  if (words[0] != kSpirvMagic) return {};  // torn or foreign file: compile again
  return words;
}

}  // namespace

std::filesystem::path shader_cache_directory() {
  if (const char* folder = std::getenv("FOVLAB_SHADER_CACHE"); folder && *folder) return folder;
  if (const char* cache = std::getenv("XDG_CACHE_HOME"); cache && *cache) {
    return std::filesystem::path(cache) / "fovlab" / "spirv";
  }
  if (const char* home = std::getenv("HOME"); home && *home) {
    return std::filesystem::path(home) / ".cache" / "fovlab" / "spirv";
  }
  return std::filesystem::temp_directory_path() / "fovlab-spirv";
}

std::string scene_shader_cache_key(const SceneSource& scene, const SceneConsumerShader& consumer) {
  ContentHash key;
  key.add(kCacheFormat).add(glslang::GetGlslVersionString()).add(kVersionLine).add(scene.text).add(consumer.source);
  for (const shaders::ShaderHeader& header : consumer.headers) key.add(header.name).add(header.text);
  return key.hex();
}

CompiledShader compile_scene_shader(const SceneSource& scene, const SceneConsumerShader& consumer) {
  CompiledShader compiled;
  compiled.cache_file =
      shader_cache_directory() / (scene.name + "-" + scene_shader_cache_key(scene, consumer) + ".spv");
  compiled.spirv = read_cached_spirv(compiled.cache_file);
  if (!compiled.spirv.empty()) {
    compiled.from_cache = true;
    return compiled;
  }
  compiled.spirv = compile_glsl(scene, consumer);
  // The cache is an optimisation: a cache folder we cannot write only costs a compile next time.
  try {
    create_output_folder(compiled.cache_file.parent_path(), "");  // never inside a participant's folder
    write_text_atomically(compiled.cache_file, std::string_view(reinterpret_cast<const char*>(compiled.spirv.data()),
                                                                compiled.spirv.size() * sizeof(uint32_t)));
  } catch (const std::exception&) {}
  return compiled;
}

}  // namespace fovlab

// Run-time scene compilation: errors name the scene file and line; the cache avoids recompiling.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/input_error.h"
#include "renderer/scene/scene_compiler.h"
#include "renderer/scene/scene_source.h"
#include "renderer/shaders/embedded_shaders.h"
#include "tests/support/temp_dir.h"

namespace fovlab {
namespace {

const SceneConsumerShader kTracer{"sphere_trace.comp.glsl", shaders::sphere_trace_source, shaders::shared_headers};

SceneSource fixture_scene() {
  return load_scene(std::string(FOVLAB_SOURCE_DIR) + "/tests/fixtures/scenes/sphere.glsl");
}

std::string compile_error(const SceneSource& scene) {
  try {
    compile_scene_shader(scene, kTracer);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

// A text no earlier run has compiled, so the cache cannot already hold it.
std::string unique_comment() {
  return "// " + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()) + "\n";
}

TEST(SceneCompile, SyntaxErrorNamesSceneFileAndLine) {
  SceneSource scene = fixture_scene();
  scene.path = "stimuli/scenes/broken.glsl";
  // Line 3 of the scene gets an undeclared identifier.
  scene.text = unique_comment() + "// line 2\nfloat broken = undeclared_thing;\n" + scene.text;
  const std::string message = compile_error(scene);
  EXPECT_EQ(message.rfind("stimuli/scenes/broken.glsl:3: ", 0), 0u) << message;
  EXPECT_NE(message.find("undeclared_thing"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
}

TEST(SceneCompile, MissingInterfaceFunctionNamesSceneAndInterface) {
  SceneSource scene = fixture_scene();
  scene.path = "my/incomplete.glsl";
  const size_t camera = scene.text.find("void scene_camera");
  ASSERT_NE(camera, std::string::npos);
  scene.text = unique_comment() + scene.text.substr(0, camera);  // drop scene_camera
  const std::string message = compile_error(scene);
  EXPECT_EQ(message.rfind("my/incomplete.glsl: does not fit the scene interface", 0), 0u) << message;
  EXPECT_NE(message.find("scene_camera"), std::string::npos) << message;
}

TEST(SceneCompile, UnchangedSceneComesFromTheCacheAndAChangedOneDoesNot) {
  SceneSource scene = fixture_scene();
  scene.text = unique_comment() + scene.text;
  const CompiledShader first = compile_scene_shader(scene, kTracer);
  EXPECT_FALSE(first.from_cache);
  ASSERT_TRUE(std::filesystem::exists(first.cache_file));
  const CompiledShader second = compile_scene_shader(scene, kTracer);
  EXPECT_TRUE(second.from_cache);
  EXPECT_EQ(second.spirv, first.spirv);

  scene.text += "\n// changed\n";
  EXPECT_FALSE(compile_scene_shader(scene, kTracer).from_cache);
}

TEST(SceneCompile, TornCacheFileIsCompiledAgain) {
  SceneSource scene = fixture_scene();
  scene.text = unique_comment() + scene.text;
  const CompiledShader first = compile_scene_shader(scene, kTracer);
  std::ofstream(first.cache_file, std::ios::binary | std::ios::trunc) << "not spir-v at all";
  const CompiledShader again = compile_scene_shader(scene, kTracer);
  EXPECT_FALSE(again.from_cache);
  EXPECT_EQ(again.spirv, first.spirv);
}

// The shared headers (renderer/shaders/shared/) enter the cache key: an edited header never meets
// SPIR-V cached from the old text.
TEST(SceneCompile, AChangedSharedHeaderChangesTheCacheKey) {
  const SceneSource scene = fixture_scene();
  std::vector<shaders::ShaderHeader> headers(shaders::shared_headers.begin(), shaders::shared_headers.end());
  ASSERT_FALSE(headers.empty());
  const std::string key = scene_shader_cache_key(scene, {kTracer.name, kTracer.source, headers});
  EXPECT_EQ(key, scene_shader_cache_key(scene, kTracer));
  for (shaders::ShaderHeader& header : headers) {
    const std::string_view original = header.text;
    const std::string edited = std::string(original) + "\n// edited\n";
    header.text = edited;
    EXPECT_NE(scene_shader_cache_key(scene, {kTracer.name, kTracer.source, headers}), key) << header.name;
    header.text = original;
  }
}

// The run-time compile includes the shared headers and refuses any other name, saying why.
TEST(SceneCompile, AnIncludeOtherThanTheSharedHeadersIsRefused) {
  const SceneSource scene = fixture_scene();
  const std::string consumer = std::string(kTracer.source) + unique_comment() + "#include \"eccentricity.glsl\"\n";
  try {
    compile_scene_shader(scene, {kTracer.name, consumer, shaders::shared_headers});
    FAIL() << "compiled";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("eccentricity.glsl"), std::string::npos) << message;
    EXPECT_NE(message.find("only the renderer's shared headers"), std::string::npos) << message;
  }
}

TEST(SceneSource, UnknownNameListsTheBuiltInScenes) {
  try {
    load_scene("no_such_scene");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("no_such_scene"), std::string::npos);
    EXPECT_NE(message.find("primitives"), std::string::npos) << message;
  }
  EXPECT_THROW(load_scene("missing/file.glsl"), InputError);
}

std::string load_error(const std::string& name_or_file) {
  try {
    load_scene(name_or_file);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(SceneSource, OnlyARegularFileWithinTheCapIsRead) {
  const testing::TempDir dir;
  const std::string folder = dir.file("folder.glsl");
  std::filesystem::create_directories(folder);
  EXPECT_EQ(load_error(folder),
            folder + ": not a regular file (a directory): expected a GLSL scene file (docs/scenes.md)");
  const std::string fifo = dir.file("fifo.glsl");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);  // was opened, and waited for a writer for ever
  EXPECT_EQ(load_error(fifo),
            fifo + ": not a regular file (a FIFO or pipe): expected a GLSL scene file (docs/scenes.md)");
  // One byte over the cap (sparse: nothing is written) was read whole and handed to the compiler.
  const std::string big = dir.write("big.glsl", "// big\n");
  std::filesystem::resize_file(big, kMaxSceneBytes + 1);
  EXPECT_EQ(load_error(big), big + ": larger than 4 MiB (" + std::to_string(kMaxSceneBytes + 1) +
                                 " bytes): expected a GLSL scene file (docs/scenes.md) of at most 4 MiB");
}

TEST(SceneSource, AByteOrderMarkIsLeftOutAndTheSceneCompiles) {
  // glslang took the mark for a stray character: "syntax error" on line 1.
  const testing::TempDir dir;
  const SceneSource plain = fixture_scene();
  const std::string comment = unique_comment();
  const SceneSource scene = load_scene(dir.write("bom.glsl", "\xEF\xBB\xBF" + comment + plain.text));
  EXPECT_EQ(scene.text, comment + plain.text);
  EXPECT_EQ(compile_error(scene), "");
}

// The three scenes of Polychronakis et al. 2023's Fig. 7 and Ye et al. 2022's three rotating patterns of Figure 12.
TEST(SceneSource, BuiltInScenesAreThoseOfTheIssues) {
  const std::vector<std::string> names = builtin_scene_names();
  for (const char* expected :
       {"primitives", "columns", "temple", "rotating-rod", "rotating-textured-rod", "rotating-texture"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
  }
}

}  // namespace
}  // namespace fovlab

// libFuzzer harness: the OBJ + MTL loader of the path tracer (renderer/path_tracing/obj_scene.h,
// parse_obj_scene), on the CPU only: no Vulkan device is made.
// Input: OBJ text, optionally followed by a line "#mtl" and MTL text, which is what every `mtllib`
// line reads (without that line, every `mtllib` is a missing library). Contract: parse_obj_scene
// throws fovlab::InputError for bad input, with a message of one line that starts with the name;
// any other exception, a crash, a sanitizer report or a hang is a bug. A scene it returns must pass
// validate() and hold what the report counts. Built two ways (tests/fuzz/fuzz.cmake):
// fovlab_obj_fuzz (clang, libFuzzer + ASan + UBSan, tinyobjloader compiled in and instrumented;
// scripts/fuzz) and fovlab_obj_corpus (corpus_runner.cpp replays tests/fuzz/corpus/obj under CTest).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/input_error.h"
#include "renderer/path_tracing/obj_scene.h"

namespace {

void expect(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "obj_fuzz: violates: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::string separator = "\n#mtl\n";
  const size_t split = input.find(separator);
  const std::string obj = input.substr(0, split);
  const bool has_library = split != std::string::npos;
  const std::string mtl = has_library ? input.substr(split + separator.size()) : std::string();
  const auto read_library = [&](const std::string& library) -> std::string {
    if (!has_library)
      throw fovlab::InputError(library + ": cannot open (no library in this input): expected an MTL material library");
    return mtl;
  };
  fovlab::ObjLoadReport report;
  fovlab::PathScene scene;
  try {
    scene = fovlab::parse_obj_scene(obj, "fuzz.obj", read_library, &report);
  } catch (const fovlab::InputError& error) {
    const std::string message = error.what();
    expect(message.rfind("fuzz.obj:", 0) == 0, "an error starts with the name");
    expect(message.find('\n') == std::string::npos, "an error is one line");
    return 0;
  }
  expect(scene.triangle_count() == report.triangles && report.triangles > 0, "the report counts the triangles");
  expect(report.triangles_without_material <= report.triangles, "at most every triangle without a material");
  try {
    validate(scene);
  } catch (const fovlab::InputError& error) {
    std::fprintf(stderr, "obj_fuzz: a loaded scene fails validate: %s\n", error.what());
    std::abort();
  }
  return 0;
}

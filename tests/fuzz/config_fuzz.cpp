// libFuzzer harness: the study-config parser (study/config/study_config.h).
// Contract: parse_study_config_text throws fovlab::InputError for bad input; any other exception,
// a crash, a sanitizer report or a hang is a bug. Built two ways (tests/fuzz/fuzz.cmake):
// fovlab_config_fuzz (clang, libFuzzer + ASan + UBSan; scripts/fuzz) and fovlab_config_corpus
// (corpus_runner.cpp replays tests/fuzz/corpus/config under CTest).
// No file writes: the parser only reads (built-in scene names from stimuli/scenes or
// $FOVLAB_SCENES_DIR; a relative scene path is looked up relative to the current directory,
// since "fuzz.toml" has no folder).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/input_error.h"
#include "study/config/study_config.h"

namespace {

// "A StudyConfig that exists is a runnable study": a few invariants the parser promises.
void expect(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "config_fuzz: parsed config violates: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    // Scene names are checked against a fixed catalog (the harness links no renderer); files are not
    // looked for.
    static const fovlab::SceneCatalog scenes{{"primitives", "columns", "temple"},
                                             {"courtyard"},
                                             ".obj",
                                             false,
                                             {"marschner-lobb", "combustion", "shepp-logan"},
                                             ".toml"};
    const fovlab::StudyConfig config = fovlab::parse_study_config_text(text, "fuzz.toml", scenes);
    expect(config.source_text == text, "source_text is the input");
    expect(!config.blocks.empty(), "at least one block");
    expect(config.stimulus.frame_count() >= 1, "at least one frame");
    expect(config.protocol.repeats >= 1, "repeats >= 1");
    expect(config.protocol.question.answers.size() ==
               fovlab::protocol_answers(config.protocol.kind, config.protocol.two_afc_question).size(),
           "one key list per answer");
    for (size_t i = 1; i < config.levels.values.size(); ++i)
      expect(config.levels.values[i - 1] < config.levels.values[i], "levels ascending");
  } catch (const fovlab::InputError&) {
    // Rejected input, as the contract says.
  }
  return 0;
}

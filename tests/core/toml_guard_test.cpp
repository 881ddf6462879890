// The shield in front of toml++ 3.3.0's undefined behaviour on some non-ASCII code points
// (core/toml_guard.h): text in strings survives exactly, elsewhere it is an error with
// its line, and the inputs the fuzzer found parse to errors, not to undefined behaviour.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "protocols/stimuli/stimulus_settings.h"
#include "core/input_error.h"
#include "study/config/study_config.h"
#include "core/toml_guard.h"

namespace fovlab {
namespace {

std::string demo_text() {
  std::ifstream in(std::filesystem::path(FOVLAB_SOURCE_DIR) / "experiments/demo.toml");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string with(std::string text, const std::string& from, const std::string& to) {
  text.replace(text.find(from), from.size(), to);
  return text;
}

TEST(ProtocolsTomlGuard, ShieldIsInvertibleAndLeavesAsciiAlone) {
  const std::string text = "a = \"été Ωμέγα Привет ⱞ〡ﬦ\uFEFE\" # ß\n";
  const std::string shielded = shield_toml_hazards(text, "x.toml");
  EXPECT_NE(shielded, text);
  EXPECT_EQ(unshield_toml_hazards(shielded), text);
  EXPECT_EQ(shield_toml_hazards("plain = 1\n", "x.toml"), "plain = 1\n");
  // U+3000 (ideographic space) and U+FEFF are handled by toml++ and left as they are.
  EXPECT_EQ(shield_toml_hazards("a = \"\u3000\uFEFF\"", "x.toml"), "a = \"\u3000\uFEFF\"");
}

TEST(ProtocolsTomlGuard, NonAsciiTextInStringsParsesExactly) {
  const std::string instructions = "Deux séquences — «vidéo» Ωμέγα Привет ⱞ";
  const StudyConfig config = parse_study_config_text(
      with(with(demo_text(), "[study]\n", "[study]\n# commentaire: été\n"), "instructions = \"Two short",
           "instructions = \"" + instructions + " Two short"),
      (std::filesystem::path(FOVLAB_SOURCE_DIR) / "experiments/demo.toml").string(), renderer_scene_catalog());
  EXPECT_EQ(config.instructions.rfind(instructions, 0), 0u) << config.instructions;
}

TEST(ProtocolsTomlGuard, HazardsOutsideStringsAreErrorsWithTheirLine) {
  for (const std::string& bad :
       {std::string("namé = 3\n"), std::string("\xcc\xaa\n"), std::string("x = \"\"\"a\\\n\u00a7\"\"\"\n")}) {
    try {
      parse_study_config_text("# first line\n" + bad, "bad.toml", renderer_scene_catalog());
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const InputError& error) {
      EXPECT_EQ(std::string(error.what()).rfind("bad.toml:", 0), 0u) << error.what();
    }
  }
  try {
    parse_study_config_text("a = 1\nb = \"\xf3\xb0\x80\x80\"\n", "private.toml", renderer_scene_catalog());  // U+F0000
    ADD_FAILURE() << "a private-use placeholder code point was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("private.toml:2: code points U+F0000"), std::string::npos) << error.what();
  }
}

// The error of parsing `text` as a config named "deep.toml" ("" and a failure when there is none).
std::string config_error(const std::string& text) {
  try {
    parse_study_config_text(text, "deep.toml", renderer_scene_catalog());
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "accepted";
  return "";
}

// The error must be the nesting guard's one line, at `line`, about `what`.
void expect_too_deep(const std::string& text, int line, const std::string& what) {
  const std::string message = config_error(text);
  const std::string limit = std::to_string(kMaxStudyConfigNesting);
  EXPECT_EQ(message.rfind("deep.toml:" + std::to_string(line) + ": " + what + " nested deeper than " + limit +
                              " levels: expected at most " + limit,
                          0),
            0u)
      << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

std::string repeated(const std::string& part, int count, const std::string& separator = "") {
  std::string text;
  for (int i = 0; i < count; ++i) text += (i ? separator : "") + part;
  return text;
}

int line_count(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

TEST(ProtocolsTomlGuard, DottedKeysOfTensOfThousandsOfPartsAreRefusedNotAStackOverflow) {
  // 40,000 parts overflowed toml++'s stack: fovlab validate crashed. Configs also come from session
  // logs' headers (replay, analyze), through the same parse_study_config_text.
  expect_too_deep("# first\n\n" + repeated("a", 40000, ".") + " = 1\n", 3, "dotted key");
  expect_too_deep(demo_text() + "[" + repeated("b", 40000, ".") + "]\n", line_count(demo_text()) + 1, "table header");
  expect_too_deep("[[" + repeated("'q.'", 40000, " . ") + "]]\n", 1, "table header");
  expect_too_deep("x = {" + repeated("c", 40000, ".") + " = 2}\n", 1, "dotted key");
}

TEST(ProtocolsTomlGuard, DeepArraysAndInlineTablesAreRefusedWithTheirLine) {
  // Within toml++'s own limit (256 levels), so only the guard refuses them.
  expect_too_deep("a = 1\nx = " + repeated("[", 100) + repeated("]", 100) + "\n", 2, "array");
  expect_too_deep("x = [\n  1,\n  " + repeated("{y = ", 100) + "0" + repeated("}", 100) + "]\n", 3, "inline table");
  // Levels add up: a table header's parts, the key's parts and the arrays around the value.
  const int limit = kMaxStudyConfigNesting;
  const auto nested = [&](int header_parts, int key_parts, int arrays) {
    return "[" + repeated("t", header_parts, ".") + "]\n" + repeated("k", key_parts, ".") + " = " +
           repeated("[", arrays) + "1" + repeated("]", arrays) + "\n";
  };
  EXPECT_NO_THROW(check_toml_nesting(nested(10, 10, limit - 20), "deep.toml", limit));
  EXPECT_THROW(check_toml_nesting(nested(10, 10, limit - 19), "deep.toml", limit), InputError);
  EXPECT_NO_THROW(check_toml_nesting(nested(10, limit - 10, 0), "deep.toml", limit));
  EXPECT_THROW(check_toml_nesting(nested(10, limit - 9, 0), "deep.toml", limit), InputError);
  EXPECT_NO_THROW(check_toml_nesting("[[" + repeated("t", limit - 1, ".") + "]]\n", "deep.toml", limit));
  EXPECT_THROW(check_toml_nesting("[[" + repeated("t", limit, ".") + "]]\n", "deep.toml", limit), InputError);
  // A config at the limit is no error of the guard's (an inline table deep in a key's array).
  EXPECT_EQ(config_error(demo_text() + "[protocol.keys]\nsame = " + repeated("[", limit - 3) +
                         repeated("]", limit - 3) + "\n")
                .find("nested deeper"),
            std::string::npos);
}

TEST(ProtocolsTomlGuard, BracketsDotsAndQuotesInStringsAndCommentsDoNotCount) {
  const std::string deep = repeated("[", 100) + repeated("{", 100) + repeated("a.", 100);
  const std::string texts[] = {
      R"(s = ")" + deep + R"(\" )" + deep + "\"\n",
      "s = '" + deep + "'\n",
      "s = \"\"\"\n" + deep + "\n\"\"\"\n",
      "s = '''" + deep + "\\'''\n",
      "# " + deep + "\n",
      R"(s = """a""""" # )" + deep + "\n",
      "\"" + deep + "\" = 1\n",
      R"(x = ["]", 1.5, 1979-05-27T07:32:00Z] # )" + deep + "\n",
  };
  for (const std::string& text : texts) EXPECT_NO_THROW(check_toml_nesting(text, "strings.toml", 4)) << text;
  // After multi-line strings and an escaped line end, lines are still counted right.
  expect_too_deep("s = \"\"\"\none\ntwo\\\n\"\"\"\nt = '''\n'''\nx = " + repeated("[", 40) + "\n", 7, "array");
}

}  // namespace
}  // namespace fovlab

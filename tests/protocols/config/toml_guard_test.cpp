// The shield in front of toml++ 3.3.0's undefined behaviour on some non-ASCII code points
// (protocols/config/toml_guard.h): text in strings survives exactly, elsewhere it is an error with
// its line, and the inputs the fuzzer found parse to errors, not to undefined behaviour.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/input_error.h"
#include "protocols/config/study_config.h"
#include "protocols/config/toml_guard.h"

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
      (std::filesystem::path(FOVLAB_SOURCE_DIR) / "experiments/demo.toml").string());
  EXPECT_EQ(config.instructions.rfind(instructions, 0), 0u) << config.instructions;
}

TEST(ProtocolsTomlGuard, HazardsOutsideStringsAreErrorsWithTheirLine) {
  for (const std::string& bad : {std::string("namé = 3\n"), std::string("\xcc\xaa\n"), std::string("x = \"\"\"a\\\n\u00a7\"\"\"\n")}) {
    try {
      parse_study_config_text("# first line\n" + bad, "bad.toml");
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const InputError& error) {
      EXPECT_EQ(std::string(error.what()).rfind("bad.toml:", 0), 0u) << error.what();
    }
  }
  try {
    parse_study_config_text("a = 1\nb = \"\xf3\xb0\x80\x80\"\n", "private.toml");  // U+F0000
    ADD_FAILURE() << "a private-use placeholder code point was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("private.toml:2: code points U+F0000"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace fovlab

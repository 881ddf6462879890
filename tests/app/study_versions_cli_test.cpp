// Config versions (study/log/study_versions.h): `fovlab run` refuses a new participant under a
// config whose content differs from the sessions already in the study folder, unless told
// --new-version, which runs it in results/<study>@v2; resuming and comment-only edits work as
// before; `fovlab analyze` states the versions it found.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::CommandResult;
using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::read_all;

CommandResult run(const std::string& arguments) {
  return fovlab::cli_test::run(arguments, "env -u DISPLAY -u WAYLAND_DISPLAY");
}

// The rating fixture with `from` replaced by `to`, beside the fixtures (its scene path is relative).
std::string rating_config(const std::string& name, const std::string& from, const std::string& to) {
  const fs::path fixtures = fs::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/studies";
  std::string text = read_all(fixtures / "rating.toml");
  if (!from.empty()) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
  const fs::path path = fixtures / ("generated_versions_" + name + ".toml");
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

TEST(StudyVersionsCli, AnEditedConfigRunsOnlyAsANewVersionAndAnalyzeNamesBoth) {
  const fs::path results = fovlab::cli_test::scratch("fovlab-study-versions-cli-test") / "results";
  fs::remove_all(results);
  const std::string tail = " --observer simulated --headless --results " + results.string();
  const std::string original = rating_config("original", "", "");
  // Comments and formatting only: the same version, the same folder.
  const std::string commented = rating_config("commented", "repeats = 2", "repeats   =   2   # per level\n# edited");
  const std::string edited = rating_config("edited", "repeats = 2", "repeats = 1");

  ASSERT_EQ(run("run " + original + " --participant P001" + tail).exit_code, 0);
  const CommandResult same = run("run " + commented + " --participant P002" + tail);
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_TRUE(fs::exists(results / "tiny_rating/P002/events.jsonl"));

  // A new participant under the edited config: refused in one line, nothing made.
  const CommandResult refused = run("run " + edited + " --participant P003" + tail);
  expect_one_line_error(refused,
                        edited + ": differs from the config 2 session(s) in " + (results / "tiny_rating").string());
  EXPECT_NE(refused.err.find("--new-version"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find((results / "tiny_rating@v2").string()), std::string::npos) << refused.err;
  EXPECT_FALSE(fs::exists(results / "tiny_rating/P003"));
  EXPECT_FALSE(fs::exists(results / "tiny_rating@v2"));

  // Told: the versioned folder, and the next participant of that version joins it.
  const CommandResult versioned = run("run " + edited + " --participant P003 --new-version" + tail);
  ASSERT_EQ(versioned.exit_code, 0) << versioned.err;
  EXPECT_NE(versioned.out.find((results / "tiny_rating@v2/P003/events.jsonl").string()), std::string::npos)
      << versioned.out;
  const CommandResult next = run("run " + edited + " --participant next --new-version" + tail);
  ASSERT_EQ(next.exit_code, 0) << next.err;
  EXPECT_TRUE(fs::exists(results / "tiny_rating@v2/P004/events.jsonl"));  // IDs unique across versions
  // The original config with --new-version stays in the first folder; an ID of another version is refused.
  ASSERT_EQ(run("run " + original + " --participant P005 --new-version" + tail).exit_code, 0);
  EXPECT_TRUE(fs::exists(results / "tiny_rating/P005/events.jsonl"));
  expect_one_line_error(run("run " + original + " --participant P003" + tail),
                        "--participant P003: already has a session in");
  // An existing participant is resumed (here: found finished) exactly as before.
  expect_one_line_error(run("run " + original + " --participant P001" + tail), "already finished this study");

  // analyze: the majority version analysed, both named in stdout and thresholds.json.
  const fs::path out = results.parent_path() / "analysis-both";
  fs::remove_all(out);
  const CommandResult both = run("analyze " + results.string() + " --out " + out.string() + " --bootstrap 0");
  ASSERT_EQ(both.exit_code, 0) << both.err;
  EXPECT_NE(both.out.find("config versions found: 2, one analysed"), std::string::npos) << both.out;
  EXPECT_NE(both.out.find("3 session(s) in " + (results / "tiny_rating").string() + ", analysed"), std::string::npos)
      << both.out;
  EXPECT_NE(both.out.find("2 session(s) in " + (results / "tiny_rating@v2").string() + ", not analysed"),
            std::string::npos)
      << both.out;
  const nlohmann::json thresholds = nlohmann::json::parse(read_all(out / "thresholds.json"));
  ASSERT_EQ(thresholds.at("config_versions").size(), 2u);
  EXPECT_TRUE(thresholds["config_versions"][0]["analysed"].get<bool>());
  EXPECT_EQ(thresholds["config_versions"][1]["sessions"], 2);
  EXPECT_EQ(thresholds.at("left_out").dump().find("another version"), std::string::npos);
  EXPECT_NE(read_all(out / "report.html").find("Config versions (only one is analysed)"), std::string::npos);

  // The new version's folder analysed on its own: its analysis goes beside its sessions.
  const CommandResult second = run("analyze " + (results / "tiny_rating@v2").string() + " --bootstrap 0");
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_TRUE(fs::exists(results / "tiny_rating@v2/analysis/thresholds.json")) << second.out;
  EXPECT_FALSE(fs::exists(results / "tiny_rating/analysis"));
}

}  // namespace

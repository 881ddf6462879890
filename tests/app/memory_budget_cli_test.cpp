// Work that would not fit in memory is refused before it starts (issue 14, point 9): validate, a
// session (StimulusLibrary::prepare), render and bench compare their estimate with the memory
// available (FOVLAB_MEMORY_LIMIT_BYTES here, MemAvailable otherwise) and exit 2 with one line naming
// what drives the estimate, the estimate and the memory available; nothing is rendered or written.
// With room enough, or without the variable, they run as before.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;
using fovlab::cli_test::CommandResult;
using fovlab::cli_test::expect_one_line_error;

const char* const kHeadless = "env -u DISPLAY -u WAYLAND_DISPLAY";

// fovlab with the memory available set to `limit` ("" : the variable unset).
CommandResult fovlab_with_limit(const std::string& arguments, const std::string& limit) {
  const std::string environment = limit.empty() ? std::string(kHeadless) + " -u FOVLAB_MEMORY_LIMIT_BYTES"
                                                : std::string(kHeadless) + " FOVLAB_MEMORY_LIMIT_BYTES=" + limit;
  return fovlab::cli_test::run(arguments, environment);
}

std::string tiny_2afc() { return (fs::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/studies/tiny_2afc.toml").string(); }

fs::path scratch(const std::string& name) { return fovlab::cli_test::scratch("fovlab-memory-cli-" + name); }

// The refusal: one line, exit 2, the fields or flags, the estimate and the limit.
void expect_refused(const CommandResult& result, const std::vector<std::string>& names) {
  expect_one_line_error(result, "FOVLAB_MEMORY_LIMIT_BYTES");
  for (const std::string& name : names) EXPECT_NE(result.err.find(name), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("needs about "), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("1000 bytes available"), std::string::npos) << result.err;
}

TEST(MemoryBudgetCli, ValidateRefusesAStudyWhosePreparedFramesDoNotFit) {
  // tiny_2afc: 10 prepared stimuli (2 blocks x 5) x 2 frames x 64x36 px x 4 bytes = 184,320 bytes.
  const CommandResult refused = fovlab_with_limit("validate " + tiny_2afc(), "1000");
  expect_refused(refused, {tiny_2afc(), "stimulus.duration_s", "stimulus.frames_per_second", "display.width_px",
                           "10 prepared stimuli x 2 frames", "64x36", "180.0 KiB"});
  EXPECT_TRUE(refused.out.empty()) << refused.out;
  // Room enough, or no limit: valid, as before.
  EXPECT_EQ(fovlab_with_limit("validate " + tiny_2afc(), "184320").exit_code, 0);
  const CommandResult unlimited = fovlab_with_limit("validate " + tiny_2afc(), "");
  EXPECT_EQ(unlimited.exit_code, 0) << unlimited.err;
  EXPECT_NE(unlimited.out.find("valid"), std::string::npos) << unlimited.out;
}

TEST(MemoryBudgetCli, SessionIsRefusedBeforeAnythingIsWritten) {
  const fs::path results = scratch("run") / "results";
  const std::string run =
      "run " + tiny_2afc() + " --participant P001 --headless --observer simulated --results " + results.string();
  expect_refused(fovlab_with_limit(run, "1000"), {"stimulus.frames_per_second", "display.width_px"});
  EXPECT_FALSE(fs::exists(results / "tiny_2afc" / "P001" / "events.jsonl")) << "a log was written";
  const CommandResult unlimited = fovlab_with_limit(run, "");
  ASSERT_EQ(unlimited.exit_code, 0) << unlimited.err;
  EXPECT_TRUE(fs::is_regular_file(results / "tiny_2afc" / "P001" / "events.jsonl"));
}

TEST(MemoryBudgetCli, RenderAndBenchRefuseFramesThatDoNotFit) {
  const fs::path folder = scratch("render");
  const fs::path image = folder / "frame.png";
  const std::string render = "render --scene primitives --width 64 --height 48 --out " + image.string();
  expect_refused(fovlab_with_limit(render, "1000"), {"--width", "--height", "64x48"});
  EXPECT_FALSE(fs::exists(image));
  const std::string bench =
      "bench --scenes primitives --spp 1 --width 64 --height 48 --repeats 1 --json " + (folder / "bench.json").string();
  expect_refused(fovlab_with_limit(bench, "1000"), {"--width", "--height", "64x48"});
  EXPECT_FALSE(fs::exists(folder / "bench.json"));
  // A huge frame against a realistic limit (1 GiB): 8192x8192 holds several GiB.
  const CommandResult huge =
      fovlab_with_limit("render --scene primitives --width 8192 --height 8192 --out " + image.string(), "1073741824");
  expect_one_line_error(huge, "8192x8192");
  EXPECT_NE(huge.err.find("GiB in memory, more than the 1.0 GiB available"), std::string::npos) << huge.err;
  // Room enough, or no limit: rendered as before.
  const CommandResult unlimited = fovlab_with_limit(render, "");
  ASSERT_EQ(unlimited.exit_code, 0) << unlimited.err;
  EXPECT_TRUE(fs::is_regular_file(image));
}

TEST(MemoryBudgetCli, ALimitThatIsNotANumberIsOneLine) {
  for (const char* limit : {"lots", "-5", "1e9", "99999999999999999999"}) {
    SCOPED_TRACE(limit);
    expect_one_line_error(fovlab_with_limit("validate " + tiny_2afc(), limit), "FOVLAB_MEMORY_LIMIT_BYTES");
  }
}

}  // namespace

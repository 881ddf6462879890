// Path-traced studies end to end (Polychronakis et al. 2021): tiny pair, ramp and slider studies of the pre-rendered
// reference (pt) against the emulated foveated path tracer (fpt) run headless with the simulated
// observer, replay --verify and analyze (also at a size whose sides are not multiples of 4); and bad
// input as one line with exit code 2 and no results written: a pt reference with a sphere-traced
// test, an fpt study on a sphere-traced scene, an unreadable frame in the pre-render cache.
// 32x20 (or 36x20) frames, 2 samples, 2 bounces, 2 frames a stimulus, modelled on experiments/fpt_*.toml.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/digest.h"
#include "core/image_io.h"
#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::CommandResult;
using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::read_all;
using fovlab::cli_test::run_in;
using fovlab::cli_test::write_file;

// A fresh working directory per test, its own top-level folder: ctest runs tests in parallel processes.
fs::path working_dir(const std::string& name) {
  return fovlab::cli_test::fresh_folder(fovlab::cli_test::scratch("fovlab-fpt-study-cli"), name);
}

void replace(std::string& text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
}

// A study of pt against fpt on the courtyard, levels foveal_deg; `protocol` is the [protocol] table's body.
std::string fpt_config(const std::string& name, const std::string& protocol, const std::string& values = "[5, 20]") {
  return "[study]\nname = \"" + name +
         "\"\nseed = 21\n\n"
         "[display]\nwidth_px = 32\nheight_px = 20\nrefresh_hz = 60\ndiagonal_in = 27\nviewing_distance_mm = 500\n\n"
         "[stimulus]\nduration_s = 0.1\nframes_per_second = 20\ncamera_start_s = 3.0\n\n"
         "[stimulus.reference]\nmethod = \"pt\"\nsamples_per_pixel = 2\nmax_bounces = 2\n\n"
         "[stimulus.test]\nmethod = \"fpt\"\nsamples_per_pixel = 2\nmax_bounces = 2\n\n"
         "[levels]\nparameter = \"foveal_aperture_deg\"\nvalues = " +
         values +
         "\nhigher_is_better = true\n\n"
         "[protocol]\n" +
         protocol +
         "\n\n[timing]\nblack_interval_s = 0.05\ninter_trial_s = 0.05\n\n"
         "[[block]]\nscene = \"courtyard\"\n";
}

std::vector<fs::path> cache_frames(const fs::path& dir) {
  std::vector<fs::path> frames;
  if (!fs::exists(dir / "stimuli/cache")) return frames;
  for (const auto& entry : fs::recursive_directory_iterator(dir / "stimuli/cache"))
    if (entry.path().extension() == ".exr") frames.push_back(entry.path());
  std::sort(frames.begin(), frames.end());
  return frames;
}

// The two frames' files swapped: both valid, each of the right size, but not what was rendered.
void swap_frame_files(const fs::path& a, const fs::path& b) {
  const std::string bytes_a = read_all(a);
  const std::string bytes_b = read_all(b);
  ASSERT_TRUE(bytes_a != bytes_b);
  write_file(a, bytes_b);
  write_file(b, bytes_a);
}

// Each frame's .sha256 written again for the bytes now there (a forger's move).
void rehash_frames(const std::vector<fs::path>& frames) {
  for (const fs::path& frame : frames)
    write_file(fs::path(frame).replace_extension(".sha256"),
               fovlab::sha256_hex(read_all(frame)) + "  " + frame.filename().string() + "\n");
}

// Run a participant, replay --verify its log, analyze the study: each exits 0. `config`: the study
// (fpt_config's by default), whose test method is `test_method`.
void run_replay_analyze(const std::string& name, const std::string& protocol, const std::string& values,
                        const std::string& config = "", const std::string& test_method = "fpt") {
  const fs::path dir = working_dir(name);
  write_file(dir / "study.toml", config.empty() ? fpt_config(name, protocol, values) : config);
  const std::string run_args =
      "run study.toml --participant next --headless --observer simulated:threshold=15 --results results";
  const CommandResult session = run_in(dir, run_args);
  ASSERT_EQ(session.exit_code, 0) << session.out << session.err;
  const fs::path log = dir / "results" / name / "P001" / "events.jsonl";
  ASSERT_TRUE(fs::is_regular_file(log)) << session.out;
  EXPECT_NE(session.out.find("(headless, virtual clock)"), std::string::npos) << session.out;
  // The session rendered its missing frames into the cache under the working directory: 2 frames of
  // one sequence shared by pt and fpt.
  EXPECT_EQ(cache_frames(dir).size(), 2u);
  // fpt is blended per refresh from the gaze, so its frames are logged; the log names both methods.
  const std::string text = read_all(log);
  EXPECT_NE(text.find("\"method\":\"" + test_method + "\""), std::string::npos);
  EXPECT_NE(text.find("\"method\":\"pt\""), std::string::npos);
  EXPECT_NE(text.find("session_end"), std::string::npos) << "the session finished";

  const CommandResult replay = run_in(dir, "replay --verify " + log.string());
  EXPECT_EQ(replay.exit_code, 0) << replay.out << replay.err;
  EXPECT_NE(replay.out.find("replay matches the log"), std::string::npos) << replay.out;

  const CommandResult analysis = run_in(dir, "analyze " + (dir / "results" / name).string());
  EXPECT_EQ(analysis.exit_code, 0) << analysis.out << analysis.err;
  EXPECT_NE(analysis.out.find("study " + name), std::string::npos) << analysis.out;
  EXPECT_NE(analysis.out.find("  threshold "), std::string::npos) << analysis.out;
  EXPECT_NE(analysis.out.find("1 participant(s)"), std::string::npos) << analysis.out;

  // A second participant: the frames come from the cache (nothing added to it), same result files.
  const auto frames_before = cache_frames(dir);
  std::vector<std::string> frame_bytes;
  for (const fs::path& frame : frames_before) frame_bytes.push_back(read_all(frame));
  const CommandResult second = run_in(dir, run_args);
  ASSERT_EQ(second.exit_code, 0) << second.out << second.err;
  EXPECT_TRUE(fs::is_regular_file(dir / "results" / name / "P002" / "events.jsonl"));
  ASSERT_EQ(cache_frames(dir), frames_before);
  for (size_t i = 0; i < frames_before.size(); ++i)
    EXPECT_TRUE(read_all(frames_before[i]) == frame_bytes[i]) << frames_before[i] << " rewritten";
}

TEST(FptStudyCli, PairRunsReplaysAndAnalyzes) {
  run_replay_analyze("tiny_fpt_pair", "kind = \"pair\"\nrepeats = 2", "[5, 20]");
}

TEST(FptStudyCli, RampRunsReplaysAndAnalyzes) {
  run_replay_analyze("tiny_fpt_ramp", "kind = \"ramp\"\nrepeats = 1", "[5, 10, 20]");
}

TEST(FptStudyCli, SliderRunsReplaysAndAnalyzes) {
  run_replay_analyze("tiny_fpt_slider", "kind = \"slider\"\nrepeats = 1\nstart_level = 10", "[5, 10, 20]");
}

// Ye et al. 2022's sampling models on the same pre-rendered frames, live per gaze sample: a pair study of
// pt against pt-rmfr over sigma, and one against pt-hyperbolic with equalise over sigma, on a frame
// no sigma divides (any size works).
TEST(FptStudyCli, PathTracedSamplingModelsRunReplayAndAnalyze) {
  const struct {
    const char* name;
    const char* method;
    const char* extra;
    const char* sigmas;
  } cases[] = {{"tiny_pt_rmfr", "pt-rmfr", "resample = \"lanczos\"\n", "[1.4, 2.6]"},
               // Equal shaded samples (equalise "on") need zones smaller than the defaults on so few pixels.
               {"tiny_pt_hyperbolic", "pt-hyperbolic",
                "equalise = \"on\"\ninner_radius_deg = 5\nouter_radius_deg = 10\n", "[1.8, 2]"}};
  for (const auto& c : cases) {
    std::string text = fpt_config(c.name, "kind = \"pair\"\nrepeats = 2", c.sigmas);
    replace(text, "method = \"fpt\"\nsamples_per_pixel = 2\nmax_bounces = 2\n",
            std::string("method = \"") + c.method + "\"\nsamples_per_pixel = 2\nmax_bounces = 2\n" + c.extra);
    replace(text, "parameter = \"foveal_aperture_deg\"", "parameter = \"sigma\"");
    replace(text, "higher_is_better = true", "higher_is_better = false");
    replace(text, "width_px = 32\nheight_px = 20", "width_px = 33\nheight_px = 19");
    run_replay_analyze(c.name, "", "", text, c.method);
  }
}

TEST(FptStudyCli, ReplayDetectsAChangedCacheFrame) {
  // The replay renders from the cache again. A cache frame changed after the session (same size, a
  // valid EXR) no longer matches its .sha256: refused naming both files (exit 2). Changed together
  // with its .sha256, it makes the frames differ from the logged hashes (exit 1).
  const std::string name = "tiny_fpt_changed";
  const fs::path dir = working_dir(name);
  write_file(dir / "study.toml", fpt_config(name, "kind = \"pair\"\nrepeats = 2"));
  const CommandResult session =
      run_in(dir, "run study.toml --participant P1 --headless --observer simulated:threshold=15 --results results");
  ASSERT_EQ(session.exit_code, 0) << session.out << session.err;
  const auto frames = cache_frames(dir);
  ASSERT_EQ(frames.size(), 2u);
  swap_frame_files(frames[0], frames[1]);  // not what was shown
  ASSERT_FALSE(::testing::Test::HasFatalFailure());
  const std::string log = (dir / "results" / name / "P1/events.jsonl").string();
  const CommandResult refused = run_in(dir, "replay --verify " + log);
  expect_one_line_error(refused, "stimuli/cache/");
  EXPECT_NE(refused.err.find(".exr: its bytes differ from frame_00000"), std::string::npos) << refused.err;
  // The hashes written again for the swapped frames (a forger's move): each frame matches its
  // .sha256, and the replay finds the frames are not the ones the log says were shown.
  rehash_frames(frames);
  const CommandResult replay = run_in(dir, "replay --verify " + log);
  EXPECT_EQ(replay.exit_code, 1) << replay.out << replay.err;
}

// Bad input: exit code 2, one line naming the problem, and no results folder.
// validate estimates the pre-render of the path-traced frames the cache lacks from one frame a
// scene, which it renders and caches; once the cache holds them all it says so.
TEST(FptStudyCli, ValidateEstimatesThePrerenderOfTheFramesNotYetCached) {
  const fs::path dir = working_dir("validate-prerender");
  write_file(dir / "study.toml", fpt_config("validate_prerender", "kind = \"pair\"\nrepeats = 1"));
  const CommandResult first = run_in(dir, "validate study.toml");
  ASSERT_EQ(first.exit_code, 0) << first.out << first.err;
  EXPECT_NE(first.out.find("courtyard                2 path-traced frames not yet cached: about "), std::string::npos)
      << first.out;
  EXPECT_NE(first.out.find("one rendered and cached: "), std::string::npos) << first.out;
  EXPECT_NE(first.out.find("including the pre-render of 2 of 2 path-traced frames not yet in stimuli/cache: about "),
            std::string::npos)
      << first.out;
  EXPECT_NE(first.out.find(" on disk (fovlab prerender renders them ahead"), std::string::npos) << first.out;
  EXPECT_EQ(cache_frames(dir).size(), 1u);  // the timed frame is kept
  const CommandResult second = run_in(dir, "validate study.toml");
  ASSERT_EQ(second.exit_code, 0) << second.out << second.err;
  EXPECT_NE(second.out.find("pre-render of 1 of 2 path-traced frames"), std::string::npos) << second.out;
  ASSERT_EQ(cache_frames(dir).size(), 2u);
  const CommandResult third = run_in(dir, "validate study.toml");
  EXPECT_NE(third.out.find("all 2 path-traced frames already in stimuli/cache"), std::string::npos) << third.out;
  // Skipped on request: nothing rendered, nothing estimated.
  const fs::path other = working_dir("validate-no-timing");
  write_file(other / "study.toml", fpt_config("validate_no_timing", "kind = \"pair\"\nrepeats = 1"));
  const CommandResult skipped = run_in(other, "validate study.toml --no-render-timing");
  ASSERT_EQ(skipped.exit_code, 0) << skipped.err;
  EXPECT_EQ(skipped.out.find("not yet cached"), std::string::npos) << skipped.out;
  EXPECT_TRUE(cache_frames(other).empty());
}

TEST(FptStudyCli, PtReferenceWithASphereTracedTestIsRefused) {
  const fs::path dir = working_dir("mixed");
  std::string text = fpt_config("tiny_mixed", "kind = \"pair\"\nrepeats = 2");
  replace(text, "method = \"fpt\"\nsamples_per_pixel = 2\nmax_bounces = 2", "method = \"gt\"");
  replace(text, "parameter = \"foveal_aperture_deg\"\nvalues = [5, 20]", "parameter = \"max_steps\"\nvalues = [4, 8]");
  write_file(dir / "mixed.toml", text);
  const std::string tail = " --participant P1 --headless --observer simulated --results results";
  const CommandResult result = run_in(dir, "run mixed.toml" + tail);
  expect_one_line_error(result, "stimulus.test.method");
  EXPECT_NE(result.err.find("mixed.toml"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("\"pt\""), std::string::npos) << result.err;
  expect_one_line_error(run_in(dir, "validate mixed.toml"), "stimulus.test.method");
  // And the other way round: a gt reference with an fpt test.
  std::string reversed = fpt_config("tiny_mixed2", "kind = \"pair\"\nrepeats = 2");
  replace(reversed, "method = \"pt\"\nsamples_per_pixel = 2\nmax_bounces = 2", "method = \"gt\"");
  write_file(dir / "reversed.toml", reversed);
  expect_one_line_error(run_in(dir, "run reversed.toml" + tail), "stimulus.test.method");
  EXPECT_FALSE(fs::exists(dir / "results"));
  EXPECT_FALSE(fs::exists(dir / "stimuli"));
}

// A sampling model whose equalise has no solution on the config's display is refused by validate and
// before a session writes anything (or pre-renders), naming the config, the stimulus, its level and
// what to change.
TEST(FptStudyCli, EqualiseWithoutASolutionIsRefusedAtValidate) {
  const fs::path dir = working_dir("equalise");
  std::string text = fpt_config("tiny_equalise", "kind = \"pair\"\nrepeats = 2", "[1.8, 4]");
  replace(text, "method = \"fpt\"",
          "method = \"pt-hyperbolic\"\nequalise = \"on\"\ninner_radius_deg = 5\nouter_radius_deg = 10");
  replace(text, "parameter = \"foveal_aperture_deg\"", "parameter = \"sigma\"");
  replace(text, "higher_is_better = true", "higher_is_better = false");
  write_file(dir / "equalise.toml", text);
  for (const std::string command :
       {"validate equalise.toml",
        "run equalise.toml --participant P1 --headless --observer simulated --results results"}) {
    const CommandResult result = run_in(dir, command);
    expect_one_line_error(result, "equalise.toml: stimulus.test at level 4 (method \"pt-hyperbolic\"): equalise:");
    EXPECT_NE(result.err.find("sigma"), std::string::npos) << result.err;
  }
  EXPECT_FALSE(fs::exists(dir / "results"));
  EXPECT_FALSE(fs::exists(dir / "stimuli"));
}

// The mixed-methods message names the key, the reference's method and the test's value ("gt"),
// like the config's other messages ("expected ..., got ...").
TEST(FptStudyCli, PtReferenceWithAGtTestMessageNamesTheTestMethod) {
  const fs::path dir = working_dir("mixed-value");
  std::string text = fpt_config("tiny_mixed", "kind = \"pair\"\nrepeats = 2");
  replace(text, "method = \"fpt\"\nsamples_per_pixel = 2\nmax_bounces = 2", "method = \"gt\"");
  replace(text, "parameter = \"foveal_aperture_deg\"\nvalues = [5, 20]", "parameter = \"max_steps\"\nvalues = [4, 8]");
  write_file(dir / "mixed.toml", text);
  const CommandResult result = run_in(dir, "validate mixed.toml");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("\"gt\""), std::string::npos)
      << "the message should say what the test's method is: " << result.err;
}

TEST(FptStudyCli, FptOnASphereTracedSceneIsRefused) {
  const fs::path dir = working_dir("scene");
  std::string text = fpt_config("tiny_scene", "kind = \"pair\"\nrepeats = 2");
  replace(text, "scene = \"courtyard\"", "scene = \"primitives\"");
  write_file(dir / "scene.toml", text);
  const CommandResult result =
      run_in(dir, "run scene.toml --participant P1 --headless --observer simulated --results results");
  expect_one_line_error(result, "block[1].scene");
  EXPECT_NE(result.err.find("primitives"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("courtyard"), std::string::npos) << "names what is expected: " << result.err;
  // A sphere-traced .glsl scene file is no path-traced scene either.
  std::string glsl = fpt_config("tiny_glsl", "kind = \"pair\"\nrepeats = 2");
  replace(glsl, "scene = \"courtyard\"",
          "scene = \"" + (fs::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/scenes/sphere.glsl").string() + "\"");
  write_file(dir / "glsl.toml", glsl);
  expect_one_line_error(run_in(dir, "run glsl.toml --participant P1 --headless --observer simulated --results results"),
                        "sphere.glsl");
  EXPECT_FALSE(fs::exists(dir / "results"));
  EXPECT_FALSE(fs::exists(dir / "stimuli"));
}

TEST(FptStudyCli, FptRunsAtSidesThatAreNotMultiplesOf4) {
  // Issue 18: a 1366x768 panel (or a 480x270 frame) could not run fpt; the zone buffers are now
  // rounded up and cropped back, so a 33x19 display runs, replays verified and analyses.
  std::string text = fpt_config("tiny_odd", "kind = \"pair\"\nrepeats = 2");
  replace(text, "width_px = 32\nheight_px = 20", "width_px = 33\nheight_px = 19");
  run_replay_analyze("tiny_odd", "", "", text);
}

// A frame whose three zones cannot fit one storage buffer on any device is refused before anything is
// rendered (not even the pt reference), naming the size and the config fields it came from.
TEST(FptStudyCli, FptFrameTooLargeForTheDeviceIsRefusedBeforeRendering) {
  const fs::path dir = working_dir("too-large");
  std::string text = fpt_config("tiny_too_large", "kind = \"pair\"\nrepeats = 2");
  replace(text, "width_px = 32", "width_px = 16384");
  replace(text, "height_px = 20", "height_px = 16384");
  write_file(dir / "large.toml", text);
  const CommandResult result =
      run_in(dir, "run large.toml --participant P1 --headless --observer simulated --results results");
  expect_one_line_error(result, "display.width_px x display.height_px = 16384x16384: ");
  EXPECT_FALSE(fs::exists(dir / "results")) << "bad input created results";
  EXPECT_FALSE(fs::exists(dir / "stimuli")) << "something was rendered";
}

// The same for a sphere-traced study: its frame named --width x --height, flags a study does not have.
TEST(FptStudyCli, SphereTracedFrameTooLargeForTheDeviceNamesTheConfigFields) {
  const fs::path dir = working_dir("gt-too-large");
  std::string text = read_all(fs::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/studies/tiny_2afc.toml");
  replace(text, "width_px = 64", "width_px = 16384");  // 16 bytes a pixel: 4 GiB, over any device's range
  replace(text, "height_px = 36", "height_px = 16384");
  replace(text, "../scenes/sphere.glsl", (fs::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/scenes/sphere.glsl").string());
  write_file(dir / "gt.toml", text);
  const CommandResult result =
      run_in(dir, "run gt.toml --participant P1 --headless --observer simulated --results results");
  expect_one_line_error(result, "display.width_px x display.height_px = 16384x16384: the frame needs 4096 MiB");
  EXPECT_EQ(result.err.find("--width"), std::string::npos) << result.err;
  EXPECT_FALSE(fs::exists(dir / "results")) << "bad input created results";
}

// Replaces a frame by its first half: the EXR's header is whole (so it counts as cached), its pixels
// are not.
void truncate_frame(const fs::path& frame) {
  const std::string bytes = read_all(frame);
  ASSERT_GT(bytes.size(), 64u);
  write_file(frame, bytes.substr(0, bytes.size() / 2));
}

TEST(FptStudyCli, UnreadableCacheFrameIsRefusedNamingItAndWritesNoResults) {
  const std::string name = "tiny_fpt_corrupt";
  const fs::path dir = working_dir("corrupt");
  write_file(dir / "study.toml", fpt_config(name, "kind = \"pair\"\nrepeats = 2"));
  const CommandResult prerender = run_in(dir, "prerender study.toml");
  ASSERT_EQ(prerender.exit_code, 0) << prerender.out << prerender.err;
  const auto frames = cache_frames(dir);
  ASSERT_EQ(frames.size(), 2u);
  truncate_frame(frames[1]);
  const std::string corrupt = read_all(frames[1]);

  const CommandResult result =
      run_in(dir, "run study.toml --participant next --headless --observer simulated:threshold=15 --results results");
  expect_one_line_error(result, frames[1].filename().string());
  EXPECT_NE(result.err.find((frames[1].parent_path().filename() / frames[1].filename()).string()), std::string::npos)
      << result.err;
  // Nothing of a session on disk: no participant folder, no log.
  if (fs::exists(dir / "results")) {
    for (const auto& entry : fs::recursive_directory_iterator(dir / "results"))
      ADD_FAILURE() << "left behind: " << entry.path();
  }
  EXPECT_TRUE(read_all(frames[1]) == corrupt) << "the bad frame is left for the user to see";
  EXPECT_EQ(cache_frames(dir), frames);

  // Not an EXR at all: the same.
  write_file(frames[1], "not an EXR");
  expect_one_line_error(
      run_in(dir, "run study.toml --participant next --headless --observer simulated:threshold=15 --results results"),
      frames[1].filename().string());
  EXPECT_FALSE(fs::exists(dir / "results" / name / "P001"));

  // Deleted, it is rendered again and the run succeeds.
  fs::remove(frames[1]);
  const CommandResult again =
      run_in(dir, "run study.toml --participant next --headless --observer simulated:threshold=15 --results results");
  ASSERT_EQ(again.exit_code, 0) << again.out << again.err;
  EXPECT_TRUE(fs::is_regular_file(dir / "results" / name / "P001" / "events.jsonl"));
}

// A hash is no seal: frames swapped before the session, each with its .sha256 written again, pass
// every check of the cache, and the session shows them and logs their hashes, so a replay from the
// same cache matches. A replay from an empty cache (--cache) renders every frame anew and finds the
// frames differ from the logged ones (exit 1).
TEST(FptStudyCli, AForgedCacheIsFoundByAReplayFromAnEmptyCache) {
  const std::string name = "tiny_fpt_forged";
  const fs::path dir = working_dir("forged");
  write_file(dir / "study.toml", fpt_config(name, "kind = \"pair\"\nrepeats = 2"));
  ASSERT_EQ(run_in(dir, "prerender study.toml").exit_code, 0);
  const auto frames = cache_frames(dir);
  ASSERT_EQ(frames.size(), 2u);
  swap_frame_files(frames[0], frames[1]);
  ASSERT_FALSE(::testing::Test::HasFatalFailure());
  rehash_frames(frames);
  ASSERT_EQ(
      run_in(dir, "run study.toml --participant P1 --headless --observer simulated:threshold=15 --results results")
          .exit_code,
      0);
  const std::string log = (dir / "results" / name / "P1/events.jsonl").string();
  EXPECT_EQ(run_in(dir, "replay --verify " + log).exit_code, 0) << "the same forged cache: nothing differs";
  const CommandResult fresh = run_in(dir, "replay --verify --cache stimuli/cache/fresh " + log);
  EXPECT_EQ(fresh.exit_code, 1) << fresh.out << fresh.err;
  EXPECT_EQ(cache_frames(dir).size(), 4u) << "the empty cache's frames rendered anew";
}

// A frame replaced and its .sha256 deleted: nothing says it is the frame rendered, so the session
// renders it again (and its hash) instead of showing it (it was shown), and the replay matches.
TEST(FptStudyCli, AFrameReplacedWithItsHashDeletedIsRenderedAgainNotShown) {
  const std::string name = "tiny_fpt_unhashed";
  const fs::path dir = working_dir("unhashed");
  write_file(dir / "study.toml", fpt_config(name, "kind = \"pair\"\nrepeats = 2"));
  ASSERT_EQ(run_in(dir, "prerender study.toml").exit_code, 0);
  const auto frames = cache_frames(dir);
  ASSERT_EQ(frames.size(), 2u);
  const std::string rendered = read_all(frames[0]);
  fovlab::Image other(32, 20, 3);
  for (float& value : other.pixels) value = 0.5f;
  fovlab::write_image(frames[0], other);
  const fs::path hash = fs::path(frames[0]).replace_extension(".sha256");
  fs::remove(hash);

  const CommandResult session =
      run_in(dir, "run study.toml --participant P1 --headless --observer simulated:threshold=15 --results results");
  ASSERT_EQ(session.exit_code, 0) << session.out << session.err;
  EXPECT_TRUE(read_all(frames[0]) == rendered) << "the replaced frame was used, not rendered again";
  EXPECT_EQ(read_all(hash), fovlab::sha256_hex(rendered) + "  " + frames[0].filename().string() + "\n");
  const CommandResult replay = run_in(dir, "replay --verify " + (dir / "results" / name / "P1/events.jsonl").string());
  EXPECT_EQ(replay.exit_code, 0) << replay.out << replay.err;
}

// A FIFO as a frame's .exr or .sha256, or an .exr linked to /dev/zero, hung the session; each is
// refused at once naming the file (exit 2, nothing written), --verify lists it, and a prerender
// renders the frame again. Every command runs under a timeout, so a regression fails, not hangs.
TEST(FptStudyCli, CacheFilesThatAreFifosOrDeviceLinksAreRefusedWithoutHanging) {
  const std::string name = "tiny_fpt_fifo";
  const fs::path dir = working_dir("fifo");
  write_file(dir / "study.toml", fpt_config(name, "kind = \"pair\"\nrepeats = 2"));
  ASSERT_EQ(run_in(dir, "prerender study.toml").exit_code, 0);
  const auto frames = cache_frames(dir);
  ASSERT_EQ(frames.size(), 2u);
  const std::string run_args =
      "run study.toml --participant P1 --headless --observer simulated:threshold=15 --results results";
  const auto expect_refused = [&](const fs::path& file, const std::string& what) {
    SCOPED_TRACE(file.string() + " " + what);
    expect_one_line_error(run_in(dir, run_args, 300), file.filename().string() + ": not a regular file" + what);
    EXPECT_FALSE(fs::exists(dir / "results" / name / "P1" / "events.jsonl"));
    const CommandResult verify = run_in(dir, "prerender study.toml --verify", 300);
    EXPECT_EQ(verify.exit_code, 1) << verify.out << verify.err;
    EXPECT_NE(verify.out.find("1 not"), std::string::npos) << verify.out;
  };
  const auto fifo_at = [](const fs::path& path) {
    fs::remove(path);
    ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  };

  fifo_at(frames[0]);
  expect_refused(frames[0], " (a FIFO or pipe)");
  ASSERT_EQ(run_in(dir, "prerender study.toml", 300).exit_code, 0);
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(frames[0]))) << "rendered again in the FIFO's place";

  const fs::path hash = fs::path(frames[1]).replace_extension(".sha256");
  fifo_at(hash);
  expect_refused(hash, " of at most 4096 bytes");
  ASSERT_EQ(run_in(dir, "prerender study.toml", 300).exit_code, 0);

  fs::remove(frames[0]);
  fs::create_symlink("/dev/zero", frames[0]);
  expect_refused(frames[0], " (a character device)");
  ASSERT_EQ(run_in(dir, "prerender study.toml", 300).exit_code, 0);
  EXPECT_EQ(run_in(dir, "prerender study.toml --verify", 300).exit_code, 0);
  const CommandResult session = run_in(dir, run_args, 300);
  EXPECT_EQ(session.exit_code, 0) << session.out << session.err;
}

// fpt frames that the pt reference does not show (here: the periphery_bounces sequence) are only
// read when blended; an unreadable one must still fail before the session writes anything.
TEST(FptStudyCli, UnreadableFptOnlyFrameIsRefusedBeforeTheSessionStarts) {
  const std::string name = "tiny_fpt_corrupt_periphery";
  const fs::path dir = working_dir("corrupt-periphery");
  std::string text = fpt_config(name, "kind = \"pair\"\nrepeats = 2");
  replace(text, "parameter = \"foveal_aperture_deg\"\nvalues = [5, 20]",
          "parameter = \"periphery_bounces\"\nvalues = [1]");
  replace(text, "method = \"fpt\"\nsamples_per_pixel = 2\nmax_bounces = 2",
          "method = \"fpt\"\nsamples_per_pixel = 2\nmax_bounces = 2\nfoveal_aperture_deg = 5");
  write_file(dir / "study.toml", text);
  const CommandResult prerender = run_in(dir, "prerender study.toml");
  ASSERT_EQ(prerender.exit_code, 0) << prerender.out << prerender.err;
  const auto frames = cache_frames(dir);
  ASSERT_EQ(frames.size(), 4u);
  fs::path periphery_frame;
  for (const fs::path& frame : frames)
    if (read_all(frame.parent_path() / "cache.json").find("max_bounces=1;") != std::string::npos)
      periphery_frame = frame;
  ASSERT_FALSE(periphery_frame.empty());
  truncate_frame(periphery_frame);

  const CommandResult result =
      run_in(dir, "run study.toml --participant P1 --headless --observer simulated:threshold=15 --results results");
  expect_one_line_error(result, periphery_frame.filename().string());
  if (fs::exists(dir / "results")) {
    for (const auto& entry : fs::recursive_directory_iterator(dir / "results")) {
      EXPECT_FALSE(entry.is_regular_file()) << "left behind: " << entry.path();
    }
  }
}

}  // namespace

// The study commands end to end (run, validate, replay, export): what they print and write, and
// bad input as one line with exit code 2 and nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "protocols/stimuli/stimulus_settings.h"
#include "study/config/study_config.h"
#include "study/log/log_estimate.h"
#include "study/schedule/study_plan.h"
#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::CommandResult;
using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::read_all;

fs::path scratch() { return fovlab::cli_test::scratch("fovlab-study-cli-test"); }

// DISPLAY is cleared: these sessions are headless whatever the machine has.
CommandResult run(const std::string& arguments) {
  return fovlab::cli_test::run(arguments, "env -u DISPLAY -u WAYLAND_DISPLAY");
}

std::string fixture(const std::string& name) {
  return (fs::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/studies" / (name + ".toml")).string();
}

fs::path write_config(const std::string& name, const std::string& from, const std::string& to) {
  std::string text = read_all(fixture("tiny_2afc"));
  text.replace(text.find(from), from.size(), to);
  // Beside the fixtures, so the relative scene path still resolves.
  const fs::path path = fs::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/studies" / ("generated_" + name + ".toml");
  std::ofstream(path) << text;
  return path;
}

TEST(StudyCli, ValidatePrintsTheSchedule) {
  const CommandResult result = run("validate " + fixture("tiny_2afc"));
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("trials 40 (8 attention checks, 0 practice), conditions 4, stimuli 10 x 2 frames"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("block sphere"), std::string::npos) << result.out;
}

TEST(StudyCli, RunNextParticipantThenReplayAndExport) {
  const fs::path results = scratch() / "results-next";
  const std::string common =
      fixture("rating") + " --participant next --observer simulated --results " + results.string();
  const CommandResult first = run("run " + common);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_NE(first.out.find("(headless, virtual clock)"), std::string::npos) << first.out;
  const CommandResult second = run("run " + common);
  ASSERT_EQ(second.exit_code, 0) << second.err;
  const fs::path log1 = results / "tiny_rating/P001/events.jsonl";
  const fs::path log2 = results / "tiny_rating/P002/events.jsonl";
  EXPECT_NE(first.out.find(log1.string()), std::string::npos) << first.out;
  EXPECT_TRUE(fs::exists(log1) && fs::exists(log2));

  const CommandResult replay = run("replay --verify " + log1.string());
  EXPECT_EQ(replay.exit_code, 0) << replay.out << replay.err;
  EXPECT_NE(replay.out.find("replay matches the log"), std::string::npos) << replay.out;

  const CommandResult exported = run("export " + (results / "tiny_rating").string());
  EXPECT_EQ(exported.exit_code, 0) << exported.err;
  const std::string csv = read_all(results / "tiny_rating/trials.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 2 * 20);  // header + two participants of 20 trials
  // A second export without --force keeps the file.
  expect_one_line_error(run("export " + (results / "tiny_rating").string()), "exists (pass --force");
  EXPECT_EQ(run("export --force " + (results / "tiny_rating").string()).exit_code, 0);

  // An altered log fails verification with exit code 1 and names the difference.
  std::string text = read_all(log1);
  const size_t at = text.find("\"answer\":\"");
  ASSERT_NE(at, std::string::npos);
  text[at + 10] = text[at + 10] == '3' ? '1' : '3';
  const fs::path altered = scratch() / "altered.jsonl";
  std::ofstream(altered, std::ios::binary) << text;
  const CommandResult bad = run("replay --verify " + altered.string());
  EXPECT_EQ(bad.exit_code, 1) << bad.out;
  EXPECT_NE(bad.out.find("event chain breaks"), std::string::npos) << bad.out;
}

TEST(StudyCli, BadInputIsOneLineWithExitCode2AndWritesNothing) {
  const fs::path results = scratch() / "results-bad";
  const std::string tail = " --observer simulated --results " + results.string();
  expect_one_line_error(run("run " + write_config("unknown_key", "[display]", "[display]\nwidht_px = 3").string() +
                            " --participant P1" + tail),
                        ".toml:7: display.widht_px: unknown key");
  expect_one_line_error(
      run("run " + write_config("bad_type", "repeats = 4", "repeats = \"four\"").string() + " --participant P1" + tail),
      "protocol.repeats: expected an integer, got a string");
  expect_one_line_error(
      run("run " + write_config("range", "refresh_hz = 60", "refresh_hz = 0").string() + " --participant P1" + tail),
      "display.refresh_hz: expected a value in [1, 1000], got 0");
  expect_one_line_error(
      run("run " + write_config("scene", "scene = \"primitives\"", "scene = \"no_such_scene\"").string() +
          " --participant P1" + tail),
      "block[2].scene: no built-in scene or file \"no_such_scene\"");
  expect_one_line_error(run("run " + fixture("tiny_2afc") + " --participant ../P1" + tail), "--participant: expected");
  expect_one_line_error(run("run " + fixture("tiny_2afc") + " --participant P1 --headless --present-device 0" + tail),
                        "--present-device 0: a headless session presents nothing");
  expect_one_line_error(run("run /no/such/study.toml --participant P1" + tail), "/no/such/study.toml: cannot open");
  expect_one_line_error(run("run " + fixture("tiny_2afc") + " --participant P1 --gaze eyes" + tail),
                        "--gaze: expected");
  expect_one_line_error(run("run " + fixture("tiny_2afc") +
                            " --participant P1 --observer simulated:slope=-1 --results " + results.string()),
                        "--observer: slope=-1");
  expect_one_line_error(run("run " + fixture("tiny_2afc") + " --participant P1 --results " + results.string()),
                        "no display");
  expect_one_line_error(run("validate " + write_config("toml", "[display]", "[display\n").string()), "not valid TOML");
  EXPECT_FALSE(fs::exists(results)) << "bad input created " << results;
  for (const char* name : {"unknown_key", "bad_type", "range", "scene", "toml"})
    fs::remove(fs::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/studies" / (std::string("generated_") + name + ".toml"));
}

// A gaze-contingent study (FIPR follows the gaze) run in a window without --gaze is refused with
// one line naming what to give, before any window or folder: DISPLAY is unset here, and the refusal
// comes before the display is looked for. A config's [gaze] require is kept, headless too
// (docs/gaze.md, "Which source a session may use").
TEST(StudyCli, AGazeContingentStudyInAWindowNeedsItsGazeSourceNamed) {
  const fs::path results = scratch() / "results-gaze";
  fs::remove_all(results);
  const std::string tail = " --results " + results.string();
  const fs::path fipr = write_config("gaze_fipr", "method = \"ipr\"", "method = \"fipr\"");
  const CommandResult refused = run("run " + fipr.string() + " --participant next" + tail);
  expect_one_line_error(refused, fipr.string() +
                                     ": a gaze-contingent study (fipr follows the gaze) in a window needs its "
                                     "gaze source named");
  EXPECT_NE(refused.err.find("give --gaze pupil[:HOST[:PORT]] for the eye tracker, or --gaze mouse for a rehearsal"),
            std::string::npos)
      << refused.err;
  // Named, the source is taken (the mouse by name: a rehearsal), and the run goes on to look for a display.
  expect_one_line_error(run("run " + fipr.string() + " --participant next --gaze mouse" + tail), "no display");
  expect_one_line_error(run("run " + fipr.string() + " --participant next --gaze pupil" + tail), "no display");

  // [gaze] require = "tracker": any other kind refused, in a window and headless, naming the line.
  const fs::path tracker = write_config("gaze_tracker", "[[block]]", "[gaze]\nrequire = \"tracker\"\n\n[[block]]");
  const std::string text = read_all(tracker);
  const int line = 1 + static_cast<int>(std::count(
                           text.begin(), text.begin() + static_cast<std::ptrdiff_t>(text.find("require")), '\n'));
  const std::string named = tracker.string() + ":" + std::to_string(line) + ": gaze.require = tracker";
  expect_one_line_error(run("run " + tracker.string() + " --participant P1 --gaze mouse" + tail),
                        "--gaze mouse: " + named + ": expected a source of that kind, got a mouse");
  expect_one_line_error(run("run " + tracker.string() + " --participant P1" + tail),
                        named + ": a session in a window needs its gaze source named; give --gaze pupil");
  const std::string simulated = " --participant P1 --headless --observer simulated" + tail;
  expect_one_line_error(run("run " + tracker.string() + simulated),
                        named + ": a headless session's default gaze is synthetic");
  expect_one_line_error(run("run " + tracker.string() + simulated + " --gaze synthetic"), "got a synthetic");
  EXPECT_FALSE(fs::exists(results)) << "a refused run wrote " << results;
  // validate says so beforehand.
  const CommandResult validated = run("validate " + fipr.string());
  EXPECT_NE(validated.out.find("gaze: gaze-contingent: a session in a window needs --gaze"), std::string::npos)
      << validated.out;
  const CommandResult validated_tracker = run("validate " + tracker.string());
  EXPECT_NE(validated_tracker.out.find("gaze: [gaze] require = tracker"), std::string::npos) << validated_tracker.out;

  // require = ["synthetic"]: a headless pilot runs, its header names the source and its validation,
  // and trials.csv says which source each trial's session had.
  const fs::path synthetic =
      write_config("gaze_synthetic", "[[block]]", "[gaze]\nrequire = [\"synthetic\"]\n\n[[block]]");
  const CommandResult pilot = run("run " + synthetic.string() + simulated);
  ASSERT_EQ(pilot.exit_code, 0) << pilot.err;
  const fs::path log = results / "simulated" / "tiny_2afc" / "P1" / "events.jsonl";
  const fs::path log_path = fs::exists(log) ? log : results / "tiny_2afc" / "P1" / "events.jsonl";
  const std::string first = read_all(log_path).substr(0, read_all(log_path).find('\n'));
  EXPECT_NE(first.find("\"gaze_source\":{\"kind\":\"synthetic\",\"requested\":false,\"require\":[\"synthetic\"],"
                       "\"spec\":\"synthetic:seed="),
            std::string::npos)
      << first;
  EXPECT_NE(first.find("\"gaze_validation\":{\"enabled\":false}"), std::string::npos) << first;
  const CommandResult exported = run("export " + log_path.parent_path().parent_path().string());
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  const std::string csv = read_all(log_path.parent_path().parent_path() / "trials.csv");
  EXPECT_NE(csv.find(",track_kind,gaze_source,late_frames\n"), std::string::npos) << csv.substr(0, 600);
  EXPECT_NE(csv.find(",synthetic,\n"), std::string::npos) << "a desktop session measures no late frames";
  for (const char* name : {"gaze_fipr", "gaze_tracker", "gaze_synthetic"})
    fs::remove(fs::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/studies" / (std::string("generated_") + name + ".toml"));
}

TEST(StudyCli, ValidateRefusesWhatCannotBeAConfigInOneLine) {
  // A directory read as an empty text ("study: missing"), /dev/zero was read for 2.2 GB, and a
  // dotted key of 40,000 parts overflowed toml++'s stack.
  const fs::path dir = scratch() / "a_folder.toml";
  fs::create_directories(dir);
  expect_one_line_error(run("validate " + dir.string()), dir.string() + ": not a regular file (a directory)");
  expect_one_line_error(run("validate /dev/zero"), "/dev/zero: not a regular file (a character device)");
  std::string key = "a";
  for (int part = 1; part < 40000; ++part) key += ".a";
  const fs::path deep = fovlab::cli_test::write_file(scratch() / "deep.toml", "# deep\n" + key + " = 1\n");
  expect_one_line_error(run("validate " + deep.string()), deep.string() + ":2: dotted key nested deeper than");
}

// A study config of `kind` with a small display, 0.5 s stimuli at 60 Hz, three levels, and attention
// checks: the sessions of every protocol, quick.
std::string protocol_config(const std::string& kind) {
  return "[study]\nname = \"log_" + kind +
         "\"\nseed = 5\n\n"
         "[display]\nwidth_px = 16\nheight_px = 12\nrefresh_hz = 60\ndiagonal_in = 27\nviewing_distance_mm = 500\n\n"
         "[stimulus]\nduration_s = 0.5\nframes_per_second = 10\n\n"
         "[stimulus.reference]\nmethod = \"gt\"\n\n[stimulus.test]\nmethod = \"ipr\"\n\n"
         "[levels]\nparameter = \"max_steps\"\nvalues = [4, 8, 16]\n\n"
         "[protocol]\nkind = \"" +
         kind + "\"\n" + (kind == "2afc" ? "question = \"same\"\n" : "") + "repeats = 2\n\n" +
         (kind == "ramp" || kind == "slider" ? "" : "[attention]\nshare = 0.3\nbreak_s = 1\nmax_errors = 3\n\n") +
         "[timing]\nblack_interval_s = 0.05\ninter_trial_s = 0.05\n\n[[block]]\nscene = \"primitives\"\n";
}

// The log size validate checks against the readers' cap is an upper bound: real logs of every
// protocol (keyed, so every event carries its MAC) stay below it, and it is not so loose that it
// refuses studies far from the cap.
TEST(StudyCli, LogsOfEveryProtocolStayWithinTheEstimate) {
  const fs::path dir = fovlab::cli_test::fresh_folder(scratch(), "log-estimate");
  const fs::path key = fovlab::cli_test::write_file(dir / "lab.key", "0123456789abcdef0123456789abcdef");
  for (const std::string kind : {"2afc", "pair", "rating", "ramp", "slider"}) {
    SCOPED_TRACE(kind);
    const fs::path config_path = fovlab::cli_test::write_file(dir / (kind + ".toml"), protocol_config(kind));
    const CommandResult session =
        fovlab::cli_test::run_in(dir, "run " + kind +
                                          ".toml --participant P1 --headless --observer simulated --results results "
                                          "--lab-key " +
                                          key.string());
    ASSERT_EQ(session.exit_code, 0) << session.out << session.err;
    const uint64_t logged = fs::file_size(dir / "results" / ("log_" + kind) / "P1" / "events.jsonl");
    const fovlab::StudyConfig config =
        fovlab::parse_study_config_file(config_path.string(), fovlab::renderer_scene_catalog());
    const fovlab::LogSizeEstimate estimate = fovlab::estimate_log_size(fovlab::make_study_plan(config, "P1"));
    EXPECT_GE(estimate.bytes, logged);
    EXPECT_LE(estimate.bytes, 4 * logged) << "logged " << logged;
  }
}

// What validate accepts, the log readers can read back: a study whose log would pass their 1 GiB cap
// (max_log_bytes) is refused in one line naming the trials, the estimate and the cap (it was
// accepted, and its log became unreadable past about 560,000 trials).
TEST(StudyCli, ValidateRefusesAStudyWhoseLogWouldPassTheReadersCap) {
  const fs::path dir = fovlab::cli_test::fresh_folder(scratch(), "log-cap");
  std::string text = protocol_config("2afc");
  const std::string repeats = "repeats = 2\n", duration = "duration_s = 0.5\n";
  text.replace(text.find(repeats), repeats.size(), "repeats = 1000\n");
  text.replace(text.find(duration), duration.size(), "duration_s = 4.0\n");  // 240 refreshes a presentation
  for (int block = 2; block <= 6; ++block)
    text += "[[block]]\nname = \"b" + std::to_string(block) + "\"\nscene = \"primitives\"\n";
  const fs::path config = fovlab::cli_test::write_file(dir / "huge.toml", text);
  const CommandResult refused = run("validate " + config.string() + " --no-render-timing");
  expect_one_line_error(refused, config.string() + ": 25716 trials: a session's log would take up to ");
  EXPECT_NE(refused.err.find("bytes (estimated from the plan, up to "), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("more than the 1073741824 bytes (1024 MiB) the log readers take"), std::string::npos)
      << refused.err;
  // A session of it is refused the same way before it writes anything.
  const fs::path results = dir / "results";
  const CommandResult run_refused = run(
      "run " + config.string() + " --participant P001 --observer simulated --headless --results " + results.string());
  expect_one_line_error(run_refused, config.string() + ": 25716 trials: a session's log would take up to ");
  EXPECT_FALSE(fs::exists(results / "log_2afc")) << "the refused session left a folder";
  text.replace(text.find("repeats = 1000\n"), std::string("repeats = 1000\n").size(), "repeats = 100\n");
  fovlab::cli_test::write_file(config, text);
  const CommandResult accepted = run("validate " + config.string() + " --no-render-timing");
  EXPECT_EQ(accepted.exit_code, 0) << accepted.err;
}

// A [conditions] file of 5,000 variants (each its own parameters, one level): validate took 418 s
// (each planned stimulus was compared with every one before it); it takes seconds. Only the result
// is checked here; the time is measured by scripts/validate-many-variants.
TEST(StudyCli, ValidateOfFiveThousandVariants) {
  const fs::path dir = fovlab::cli_test::fresh_folder(scratch(), "many-variants");
  std::string text = protocol_config("2afc");
  const std::string levels = "[levels]\nparameter = \"max_steps\"\nvalues = [4, 8, 16]\n";
  text.replace(text.find(levels), levels.size(),
               "[levels]\nparameter = \"max_steps\"\n\n[conditions]\nfile = \"conditions.csv\"\n");
  std::string csv = "variant,max_steps,hit_threshold\n";
  for (int variant = 0; variant < 5000; ++variant) {
    char row[64];
    std::snprintf(row, sizeof row, "v%d,16,%.4f\n", variant, 0.1 + variant * 0.0001);
    csv += row;
  }
  fovlab::cli_test::write_file(dir / "conditions.csv", csv);
  const fs::path config = fovlab::cli_test::write_file(dir / "study.toml", text);
  const CommandResult result = run("validate " + config.string() + " --no-render-timing");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("conditions 5000, stimuli 5001 x 5 frames"), std::string::npos) << result.out;
}

}  // namespace

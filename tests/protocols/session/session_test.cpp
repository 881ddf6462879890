// Sessions end to end, in process: every protocol runs headless with the simulated observer, its
// log replays and verifies, a crash at any event (or inside a line) resumes to exactly the trials
// of an uninterrupted run, tampering is detected, and bad input writes nothing.
#include <gtest/gtest.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "analysis/report/report.h"
#include "analysis/study/study_analysis.h"
#include "analysis/study/study_data.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "core/input_error.h"
#include "core/image_io.h"
#include "display/frame_io.h"
#include "display/text_screen.h"
#include "protocols/session/replay.h"
#include "protocols/session/session_run.h"
#include "protocols/session/session.h"
#include "protocols/session/trials_export.h"
#include "study/log/log_events.h"
#include "tests/protocols/session/session_test_support.h"
#include "tests/support/forged_log.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;
using test::fixture_with;
using test::fresh_folder;
using test::read_file;
using test::replay;
using test::resume_after_cut;
using test::simulated;
using test::study_fixture;
using test::trial_summary;

class EveryProtocol : public ::testing::TestWithParam<const char*> {};

TEST_P(EveryProtocol, RunsHeadlessReplaysAndExports) {
  const fs::path results = fresh_folder(std::string("protocol-") + GetParam());
  const StudyConfig config = parse_study_config_file(study_fixture(GetParam()).string(), renderer_scene_catalog());
  const SessionOutcome outcome = run_session(config, simulated(results));
  EXPECT_TRUE(outcome.finished);
  EXPECT_FALSE(outcome.resumed);
  EXPECT_EQ(outcome.trials_completed, outcome.trials_total);
  EXPECT_GT(outcome.trials_total, 0);

  const ReplayOutcome replayed = replay(outcome.log_path);
  EXPECT_EQ(replayed.difference_count, 0) << (replayed.differences.empty() ? "" : replayed.differences.front());
  EXPECT_EQ(replayed.trials, outcome.trials_total);
  EXPECT_GT(replayed.presents_checked, replayed.frames_rendered);  // frames are held for several refreshes

  const std::string csv = export_trials_csv({outcome.log_path});
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), outcome.trials_total + 1);

  // Every event the run wrote reads strictly as its struct (study/log/log_events.h), which writes
  // back the same text (less the writer's chain).
  for (nlohmann::json event : read_event_log(outcome.log_path).events) {
    const LogEvent typed = parse_log_event(event);
    event.erase("chain");
    EXPECT_EQ(to_json(typed).dump(), event.dump());
  }
}

INSTANTIATE_TEST_SUITE_P(Session, EveryProtocol, ::testing::Values("tiny_2afc", "pair", "ramp", "slider", "rating"));

TEST(Session, RampAnswersEveryStepAndSliderSavesALevel) {
  const fs::path results = fresh_folder("ramp-slider");
  for (const char* name : {"ramp", "slider"}) {
    const SessionOutcome outcome = run_session(
        parse_study_config_file(study_fixture(name).string(), renderer_scene_catalog()), simulated(results));
    const SessionRecord record = read_session_record(read_event_log(outcome.log_path));
    for (const RecordedTrial& trial : record.trials) {
      const size_t steps = trial.start.sequence.size();
      if (std::string(name) == "ramp") {
        EXPECT_EQ(trial.responses.size(), steps - 1);  // an answer at every step after the first
        EXPECT_EQ(trial.stimuli.size(), steps);
      } else {
        ASSERT_FALSE(trial.responses.empty());
        EXPECT_EQ(trial.responses.front().answer, "reference");
        EXPECT_EQ(trial.responses.back().answer, "save");
        ASSERT_EQ(trial.slider_saved.size(), 1u);  // the only other event of a slider trial
        EXPECT_TRUE(trial.breaks.empty());
        EXPECT_EQ(trial.slider_saved.front().trial, trial.index);
      }
    }
  }
}

TEST(Session, QuestionScreenPutsEachKeyOnALineOfItsOwn) {
  // Issue 18: "S: same    D: different" reached the screen as "S: same D: different" (the text
  // screen joins runs of spaces). Each answer's first key now has a line of its own, and the
  // screen's layout keeps them apart.
  for (const char* name : {"tiny_2afc", "pair", "ramp", "rating"}) {
    SCOPED_TRACE(name);
    const StudyConfig config = parse_study_config_file(study_fixture(name).string(), renderer_scene_catalog());
    const QuestionConfig& question = config.protocol.question;
    const std::string text = question_screen_text(question);
    EXPECT_EQ(text.rfind(question.text + "\n\n", 0), 0u) << text;
    std::vector<std::string> expected;
    for (const auto& [answer, keys] : question.answers) {
      std::string key = keys.front();
      if (key.size() == 1) key[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(key[0])));
      expected.push_back(key + ": " + answer);
    }
    const std::vector<std::string> lines = wrap_text(text, 4000, 24, find_font_path());
    ASSERT_GE(lines.size(), expected.size());
    const std::vector<std::string> last(lines.end() - static_cast<long>(expected.size()), lines.end());
    EXPECT_EQ(last, expected);
  }
}

TEST(Session, ParticipantFieldsAreAskedKeptInTheHeaderAndExported) {
  // Issue 18: [participant] fields, given on the command line or asked, in the header and trials.csv.
  const StudyConfig config =
      fixture_with("tiny_2afc", "[[block]]", "[participant]\nfields = [\"age\", \"handedness\"]\n\n[[block]]");
  ASSERT_EQ(config.participant_fields, (std::vector<std::string>{"age", "handedness"}));
  const fs::path results = fresh_folder("fields");
  SessionOptions options = simulated(results);
  options.participant_fields = {{"age", "31"}};
  std::vector<std::string> asked;
  options.ask_participant_field = [&](const std::string& name) {
    asked.push_back(name);
    return std::string("left");
  };
  const SessionOutcome outcome = run_session(config, options);
  ASSERT_TRUE(outcome.finished);
  EXPECT_EQ(asked, std::vector<std::string>{"handedness"});  // only what the command line left out
  const SessionRecord record = read_session_record(read_event_log(outcome.log_path));
  EXPECT_EQ(record.header["participant_fields"], nlohmann::json({{"age", "31"}, {"handedness", "left"}}));
  const std::string csv = export_trials_csv({outcome.log_path});
  const std::string first_line = csv.substr(0, csv.find('\n'));
  EXPECT_TRUE(first_line.ends_with(",field_age,field_handedness,late_frames")) << first_line;
  const std::string second_line =
      csv.substr(csv.find('\n') + 1, csv.find('\n', csv.find('\n') + 1) - csv.find('\n') - 1);
  EXPECT_EQ(second_line.substr(second_line.size() - 9), ",31,left,") << second_line;  // late_frames empty: a desktop

  // A field the config does not have, and a value with a control character: refused, nothing written.
  SessionOptions unknown = simulated(results, "P2");
  unknown.participant_fields = {{"colour", "red"}};
  EXPECT_THROW(run_session(config, unknown), InputError);
  SessionOptions control = simulated(results, "P3");
  control.participant_fields = {{"age", "3\n1"}};
  EXPECT_THROW(run_session(config, control), InputError);
  EXPECT_FALSE(fs::exists(results / "tiny_2afc" / "P2" / "events.jsonl"));
  EXPECT_FALSE(fs::exists(results / "tiny_2afc" / "P3" / "events.jsonl"));
  // A human's missing field with nobody to ask is refused before anything is written.
  SessionOptions human = simulated(results, "P4");
  human.observer.clear();
  human.headless = false;
  EXPECT_THROW(
      {
        try {
          run_session(config, human);
        } catch (const InputError& error) {
          EXPECT_NE(std::string(error.what()).find("--field age=VALUE"), std::string::npos) << error.what();
          throw;
        }
      },
      InputError);
  EXPECT_FALSE(fs::exists(results / "tiny_2afc" / "P4" / "events.jsonl"));
}

TEST(Session, HeadlessScreenshotsSaveEveryKindOfScreen) {
  // Issue 18: --screenshots was ignored with --headless and saved only two screens. Now the first
  // screen of each kind is saved; headless, the frame itself (what a window would have shown).
  const fs::path results = fresh_folder("screenshots");
  const StudyConfig config = parse_study_config_file(study_fixture("tiny_2afc").string(), renderer_scene_catalog());
  SessionOptions options = simulated(results);
  options.screenshots_dir = (results / "shots").string();
  const SessionOutcome outcome = run_session(config, options);
  ASSERT_TRUE(outcome.finished);
  std::map<std::string, std::string> hashes;
  for (const char* kind : {"instructions", "stimulus", "question", "end"}) {
    SCOPED_TRACE(kind);
    const fs::path path = results / "shots" / (std::string(kind) + ".png");
    ASSERT_TRUE(fs::is_regular_file(path));
    const Rgba8Frame frame = image_to_frame(read_image(path));
    EXPECT_EQ(frame.width, config.display.width_px);
    EXPECT_EQ(frame.height, config.display.height_px);
    hashes[kind] = frame_hash(frame);
  }
  // Four different screens, and the stimulus is the first frame the log says was presented.
  EXPECT_EQ(
      std::set<std::string>({hashes["instructions"], hashes["stimulus"], hashes["question"], hashes["end"]}).size(),
      4u);
  const SessionRecord record = read_session_record(read_event_log(outcome.log_path));
  ASSERT_FALSE(record.trials.empty());
  ASSERT_FALSE(record.trials.front().stimuli.empty());
  const nlohmann::json first = to_json(record.trials.front().stimuli.front());
  size_t last_of_frame0 = 0;
  for (size_t i = 0; i < first["frame"].size(); ++i)
    if (first["frame"][i] == 0) last_of_frame0 = i;
  EXPECT_EQ(hashes["stimulus"], first["hash"][last_of_frame0].get<std::string>());
}

TEST(Session, FixationCountdownBreaksAndTheExcludedParticipantsMessage) {
  // Issue 18: a fixation cross before each trial (timing.fixation_s), breaks that count down and
  // then wait for a key, and a message for an excluded participant (attention.excluded_message).
  std::string text = read_file(study_fixture("tiny_2afc"));
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{"inter_trial_s = 0.1", "inter_trial_s = 0.1\nfixation_s = 0.25"},
        {"max_errors = 100", "max_errors = 2\nexcluded_message = \"Thanks: the session ends here.\""}}) {
    ASSERT_NE(text.find(from), std::string::npos) << from;
    text.replace(text.find(from), from.size(), to);
  }
  const StudyConfig config =
      parse_study_config_text(text, study_fixture("tiny_2afc").string(), renderer_scene_catalog());
  EXPECT_EQ(config.timing.fixation_s, 0.25);
  EXPECT_EQ(config.attention.excluded_message, "Thanks: the session ends here.");
  const fs::path results = fresh_folder("screens");
  SessionOptions options = simulated(results);
  options.observer = "simulated:guess=0.6,seed=3";  // wrong at two attention checks early on
  options.screenshots_dir = (results / "shots").string();
  const SessionOutcome outcome = run_session(config, options);
  ASSERT_TRUE(outcome.excluded);
  for (const char* kind : {"fixation", "break", "break_end", "excluded"})
    EXPECT_TRUE(fs::is_regular_file(results / "shots" / (std::string(kind) + ".png"))) << kind;
  const SessionRecord record = read_session_record(read_event_log(outcome.log_path));
  // Each trial's first stimulus starts at least the fixation's 0.25 s after the trial started.
  ASSERT_FALSE(record.trials.empty());
  for (const RecordedTrial& trial : record.trials) {
    ASSERT_FALSE(trial.stimuli.empty());
    EXPECT_GE(trial.stimuli.front().onset_s - trial.start.stamp.t.value_or(0.0), 0.25 - 1e-9) << trial.index;
  }
  // The break lasts its 2 s, then waits for the key (the simulated observer's 2 s).
  ASSERT_FALSE(record.trials.empty());
  bool found = false;
  for (const RecordedTrial& trial : record.trials)
    for (const BreakEvent& taken : trial.breaks) {
      found = true;
      EXPECT_GE(taken.duration_s, config.attention.break_s + 1.0);
    }
  EXPECT_TRUE(found) << "no attention-check break";
}

TEST(Session, StoppedAtABreaksKeyTheFailedCheckStaysCounted) {
  // Review of issue 18's breaks: the wait for a key after a wrong attention check's break can be
  // where a participant closes the window. The trial must be complete by then, or a resumed
  // session would ask the check again and forget the error. The session is stopped at that exact
  // moment through FOVLAB_TEST_CLOSE_AT_S (core/test_pause.h) on the headless clock.
  const StudyConfig config = fixture_with("tiny_2afc", "max_errors = 100", "max_errors = 5");
  const std::string observer = "simulated:guess=0.6,seed=3";  // wrong at an attention check early on
  const fs::path uninterrupted = fresh_folder("break-stop-reference");
  SessionOptions options = simulated(uninterrupted);
  options.observer = observer;
  const SessionOutcome reference = run_session(config, options);
  ASSERT_TRUE(reference.finished);
  const SessionRecord full = read_session_record(read_event_log(reference.log_path));
  const RecordedTrial* failed = nullptr;
  for (const RecordedTrial& trial : full.trials)
    if (!failed && trial.attention_check && trial.attention_check->correct == false && !trial.breaks.empty())
      failed = &trial;
  ASSERT_NE(failed, nullptr) << "no failed attention check with a break";
  const BreakEvent& taken = failed->breaks.front();
  // Halfway through the countdown: the session's next wait is the break's "press a key".
  const double close_at_s = taken.start_s + 0.5 * config.attention.break_s;

  const fs::path stopped = fresh_folder("break-stop");
  options = simulated(stopped);
  options.observer = observer;
  ::setenv("FOVLAB_TEST_CLOSE_AT_S", std::to_string(close_at_s).c_str(), 1);
  const SessionOutcome paused = run_session(config, options);
  ::unsetenv("FOVLAB_TEST_CLOSE_AT_S");
  EXPECT_FALSE(paused.finished);
  const SessionRecord at_pause = read_session_record(read_event_log(paused.log_path));
  ASSERT_FALSE(at_pause.trials.empty());
  const RecordedTrial& last = at_pause.trials.back();
  EXPECT_EQ(last.index, failed->index) << "the failed check's trial is the last complete one";
  ASSERT_TRUE(last.attention_check.has_value());
  EXPECT_EQ(last.attention_check->correct, std::optional<bool>(false));
  EXPECT_EQ(last.breaks.size(), 1u);

  // Resumed: the same trials and answers as the uninterrupted session, the check not asked again.
  const SessionOutcome resumed = run_session(config, options);
  ASSERT_TRUE(resumed.finished);
  EXPECT_EQ(trial_summary(resumed.log_path), trial_summary(reference.log_path));
}

TEST(Session, ResumesAfterACrashAtAnyEventToTheSameTrials) {
  const fs::path results = fresh_folder("resume");
  const StudyConfig config = parse_study_config_file(study_fixture("pair").string(), renderer_scene_catalog());
  const SessionOutcome reference = run_session(config, simulated(results / "whole"));
  const std::vector<std::string> expected = trial_summary(reference.log_path);
  const std::string whole = read_file(reference.log_path);
  std::vector<size_t> line_ends;
  for (size_t i = 0; i < whole.size(); ++i)
    if (whole[i] == '\n') line_ends.push_back(i + 1);
  ASSERT_GT(line_ends.size(), 10u);

  // Cut after 1, 2, 5, ... events, before session_end (the log ends with session_end and its seal),
  // and inside a line (a torn write), then resume until done.
  const std::vector<size_t> cuts = {line_ends[0],
                                    line_ends[1],
                                    line_ends[4],
                                    line_ends[line_ends.size() / 2] - 7,
                                    line_ends[line_ends.size() - 3],
                                    line_ends[line_ends.size() / 3] + 11};
  for (size_t cut : cuts) {
    SCOPED_TRACE("cut at byte " + std::to_string(cut));
    const auto [resumed, log_path] = resume_after_cut(config, simulated(results), results, whole, cut);
    EXPECT_TRUE(resumed.resumed);
    EXPECT_TRUE(resumed.finished);
    EXPECT_EQ(trial_summary(resumed.log_path), expected);
    const bool torn = std::find(line_ends.begin(), line_ends.end(), cut) == line_ends.end();
    EXPECT_EQ(fs::exists(log_path + ".torn-1"), torn);
    EXPECT_EQ(replay(resumed.log_path).difference_count, 0);
  }
}

TEST(Session, ACrashBeforeTheHeaderWasCompleteStartsAfresh) {
  const fs::path results = fresh_folder("no-header");
  const StudyConfig config = parse_study_config_file(study_fixture("rating").string(), renderer_scene_catalog());
  for (const std::string& left_behind : {std::string(), std::string("{\"event\":\"session_hea")}) {
    const std::string participant = left_behind.empty() ? "Empty" : "Torn";
    const std::string log_path = session_log_path(results.string(), config.name, participant);
    fs::create_directories(fs::path(log_path).parent_path());
    std::ofstream(log_path, std::ios::binary) << left_behind;
    const SessionOutcome outcome = run_session(config, simulated(results, participant));
    EXPECT_FALSE(outcome.resumed);
    EXPECT_TRUE(outcome.finished);
    EXPECT_EQ(outcome.trials_completed, outcome.trials_total);
    EXPECT_EQ(fs::exists(log_path + ".torn-1"), !left_behind.empty());
    if (!left_behind.empty()) {
      EXPECT_EQ(read_file(log_path + ".torn-1"), left_behind);
    }
    EXPECT_EQ(replay(log_path).difference_count, 0);
  }
}

TEST(Session, ExcludesAfterMaxAttentionErrors) {
  const fs::path results = fresh_folder("exclude");
  const StudyConfig config = fixture_with("tiny_2afc", "max_errors = 100", "max_errors = 2");
  SessionOptions options = simulated(results);
  options.observer = "simulated:guess=0.95,lapse=0.01";  // sees differences everywhere
  const SessionOutcome outcome = run_session(config, options);
  EXPECT_TRUE(outcome.excluded);
  EXPECT_LT(outcome.trials_completed, outcome.trials_total);
  const SessionRecord record = read_session_record(read_event_log(outcome.log_path));
  EXPECT_TRUE(record.excluded);
  EXPECT_EQ(record.attention_errors, 2);
  EXPECT_EQ(record.end_reason, "excluded");
  int breaks = 0;
  for (const RecordedTrial& trial : record.trials)
    for (const BreakEvent& pause : trial.breaks) breaks += pause.reason == "attention_check" ? 1 : 0;
  EXPECT_EQ(breaks, 1);  // after the first error; the second ends the session
  // A finished (excluded) participant cannot run again.
  EXPECT_THROW(run_session(config, options), InputError);

  // A crash right after the trial that reached max_errors, before "excluded" was written: the
  // resumed run excludes at once and runs no further trial.
  const std::string whole = read_file(outcome.log_path);
  const size_t excluded_at = whole.find("\"event\":\"excluded\"");
  ASSERT_NE(excluded_at, std::string::npos);
  const fs::path cut_folder = results / "cut";
  const std::string cut_log = session_log_path(cut_folder.string(), config.name, "P1");
  fs::create_directories(fs::path(cut_log).parent_path());
  std::ofstream(cut_log, std::ios::binary) << whole.substr(0, whole.rfind('\n', excluded_at) + 1);
  SessionOptions cut_options = options;
  cut_options.results_dir = cut_folder.string();
  const SessionOutcome resumed = run_session(config, cut_options);
  const SessionRecord after = read_session_record(read_event_log(resumed.log_path));
  EXPECT_TRUE(resumed.excluded);
  EXPECT_TRUE(after.excluded);
  EXPECT_EQ(after.end_reason, "excluded");
  EXPECT_EQ(after.trials.size(), record.trials.size());
}

TEST(Session, ReplayDetectsAnAlteredResponseOrFrame) {
  const fs::path results = fresh_folder("tamper");
  const SessionOutcome outcome = run_session(
      parse_study_config_file(study_fixture("tiny_2afc").string(), renderer_scene_catalog()), simulated(results));
  const std::string original = read_file(outcome.log_path);
  const auto altered_copy = [&](const std::string& from, const std::string& to) {
    std::string text = original;
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    const fs::path path = results / ("altered" + std::to_string(text.size()) + from.substr(0, 3) + ".jsonl");
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
  };
  const ReplayOutcome answer = replay(altered_copy("\"answer\":\"same\"", "\"answer\":\"different\""));
  EXPECT_GE(answer.difference_count, 2);  // the chain, and the observer's answer
  const ReplayOutcome frame = replay(altered_copy("\"hash\":[\"", "\"hash\":[\"0"));
  EXPECT_GE(frame.difference_count, 1);
  bool hash_named = false;
  for (const std::string& difference : frame.differences)
    hash_named |= difference.find("frame hash") != std::string::npos;
  EXPECT_TRUE(hash_named);
}

TEST(Session, BadInputWritesNothingAndKeepsExistingLogs) {
  const fs::path results = fresh_folder("bad-input");
  const StudyConfig config = parse_study_config_file(study_fixture("tiny_2afc").string(), renderer_scene_catalog());
  SessionOptions options = simulated(results, "../escape");
  EXPECT_THROW(run_session(config, options), InputError);
  EXPECT_TRUE(fs::is_empty(results));

  // A results "folder" that is a file.
  std::ofstream(results / "a_file") << "x";
  EXPECT_THROW(run_session(config, simulated(results / "a_file" / "sub")), InputError);

  // A log of this participant made with another config: refused, log untouched.
  const SessionOutcome first = run_session(config, simulated(results, "P2"));
  const std::string before = read_file(first.log_path);
  const StudyConfig changed = fixture_with("tiny_2afc", "repeats = 4", "repeats = 2");
  try {
    run_session(changed, simulated(results, "P2"));
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("differs from the config"), std::string::npos) << error.what();
  }
  EXPECT_EQ(read_file(first.log_path), before);
  // Finished: refused, untouched.
  EXPECT_THROW(run_session(config, simulated(results, "P2")), InputError);
  EXPECT_EQ(read_file(first.log_path), before);
  // Headless without an observer, and mouse gaze headless.
  SessionOptions human = simulated(results, "P3");
  human.observer.clear();
  EXPECT_THROW(run_session(config, human), InputError);
  SessionOptions mouse = simulated(results, "P3");
  mouse.gaze = "mouse";
  EXPECT_THROW(run_session(config, mouse), InputError);
  EXPECT_FALSE(fs::exists(results / config.name / "P3"));
}

// tiny_2afc with an eye-tracker validation and a rest between its two blocks.
StudyConfig validated_config(const std::string& validation) {
  std::string text = read_file(study_fixture("tiny_2afc"));
  const std::string from = "inter_trial_s = 0.1";
  text.replace(text.find(from), from.size(), from + "\nrest_between_blocks_s = 1");
  // The pyramid the logs of schema 1-9 showed, named: a test relabels this study's log as schema 6.
  const std::string test = "method = \"ipr\"";
  text.replace(text.find(test), test.size(), test + "\ncoarse_test = \"ray\"\nmin_filter_size = 3");
  text += "\n[validation]\n" + validation;
  return parse_study_config_text(text, study_fixture("tiny_2afc").string(), renderer_scene_catalog());
}

// The session's log events of one kind, in order.
std::vector<nlohmann::json> events_of(const std::string& log_path, const std::string& kind) {
  std::vector<nlohmann::json> found;
  for (const nlohmann::json& event : read_event_log(log_path).events)
    if (event_kind(event) == kind) found.push_back(event);
  return found;
}

TEST(SessionValidation, ASimulatedParticipantPassesAtTheStartAndAfterTheRest) {
  // Issue 18: targets before the first trial and after breaks, accuracy and precision in degrees
  // from the gaze source, logged. The synthetic source looks at each target exactly.
  const StudyConfig config = validated_config("targets = 5\ntarget_s = 0.5\nsettle_s = 0.2\n");
  const fs::path results = fresh_folder("validation-pass");
  SessionOptions options = simulated(results);
  options.screenshots_dir = (results / "shots").string();
  const SessionOutcome outcome = run_session(config, options);
  ASSERT_TRUE(outcome.finished);
  const std::vector<nlohmann::json> validations = events_of(outcome.log_path, TrackerValidationEvent::kind);
  ASSERT_EQ(validations.size(), 2u);
  const TrackerValidationEvent start = parse_tracker_validation(validations[0]);
  EXPECT_EQ(start.reason, "start");
  EXPECT_EQ(parse_tracker_validation(validations[1]).reason, "rest");
  EXPECT_TRUE(start.passed);
  EXPECT_EQ(start.attempt, 1);
  ASSERT_EQ(start.targets.size(), 5u);
  // The centre first; each target's refreshes from 0.2 s to 0.5 s measured at 60 Hz (12 to 30).
  EXPECT_DOUBLE_EQ(start.targets[0].x_px, 32.0);
  EXPECT_DOUBLE_EQ(start.targets[0].y_px, 18.0);
  for (const ValidationTarget& target : start.targets) {
    EXPECT_EQ(target.samples, 19);
    EXPECT_EQ(target.valid_samples, 19);
    // The target's centre rounded to the logged 0.01 px: accuracy below a hundredth of a degree.
    EXPECT_LT(target.accuracy_deg.value_or(1.0), 0.01);
    EXPECT_EQ(target.precision_deg.value_or(1.0), 0.0);
  }
  // Validation comes before the block it precedes, after the instructions and the rest.
  const auto events = read_event_log(outcome.log_path).events;
  std::vector<std::string> order;
  for (const nlohmann::json& event : events) {
    const std::string kind = event_kind(event);
    if (kind == "instructions" || kind == "block_start" || kind == TrackerValidationEvent::kind ||
        (kind == "break" && event["reason"] == "rest"))
      order.push_back(kind);
  }
  EXPECT_EQ(order, (std::vector<std::string>{"instructions", "tracker_validation", "block_start", "break",
                                             "tracker_validation", "block_start"}));
  for (const char* kind : {"validation", "validation_target"})
    EXPECT_TRUE(fs::is_regular_file(results / "shots" / (std::string(kind) + ".png"))) << kind;

  // The analysis reports them per participant, in participants.csv too.
  const analysis::StudyData data = analysis::load_study({(results / config.name).string()});
  analysis::AnalysisOptions analysis_options;
  analysis_options.bootstrap_samples = 0;
  const analysis::AnalysisResult result = analysis::analyse_study(data, analysis_options);
  ASSERT_EQ(result.participants.size(), 1u);
  const analysis::ValidationSummary& summary = result.participants[0].validation;
  EXPECT_EQ(summary.attempts, 2);
  EXPECT_EQ(summary.passed, 2);
  EXPECT_LT(summary.worst_accuracy_deg.value_or(1.0), 0.01);
  EXPECT_EQ(summary.mean_precision_deg, 0.0);
  analysis::write_analysis_report(result, (results / "analysis").string());
  const std::string csv = read_file(results / "analysis" / "participants.csv");
  EXPECT_NE(csv.find("validation_attempts,validations_passed,validation_accuracy_deg"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",2,2,0.00"), std::string::npos) << csv;
}

TEST(SessionValidation, FailingEveryAttemptPausesTheSessionAndResumingValidatesFirst) {
  // A trace source runs it the same way: gaze held at the screen's centre misses the outer
  // targets by 8 degrees, so each attempt fails; after max_attempts the session pauses, with no
  // trial run. Resumed with a source that passes, it validates again, then runs every trial.
  const StudyConfig config = validated_config("targets = 9\ntarget_s = 0.4\nsettle_s = 0.1\nmax_attempts = 2\n");
  const fs::path results = fresh_folder("validation-fail");
  const fs::path trace = results / "centre.csv";
  fs::create_directories(results);
  {
    std::ofstream out(trace);  // a 120 Hz tracker, the gaze at the centre for a minute
    out << "time_s,x_px,y_px\n";
    for (int i = 0; i < 120 * 60; ++i) out << i / 120.0 << ",32,18\n";
  }
  SessionOptions options = test::simulated_on_trace(results, trace);
  const SessionOutcome paused = run_session(config, options);
  EXPECT_FALSE(paused.finished);
  EXPECT_EQ(paused.trials_completed, 0);
  EXPECT_NE(paused.stop_reason.find("eye-tracker validation did not pass in 2 attempts"), std::string::npos)
      << paused.stop_reason;
  std::vector<nlohmann::json> validations = events_of(paused.log_path, TrackerValidationEvent::kind);
  ASSERT_EQ(validations.size(), 2u);
  for (int attempt = 0; attempt < 2; ++attempt) {
    const TrackerValidationEvent failed = parse_tracker_validation(validations[size_t(attempt)]);
    EXPECT_EQ(failed.attempt, attempt + 1);
    EXPECT_FALSE(failed.passed);
    ASSERT_EQ(failed.targets.size(), 9u);
    EXPECT_NEAR(failed.targets[0].accuracy_deg.value_or(-1.0), 0.0, 1e-9);  // the centre, first
    EXPECT_GT(failed.accuracy_deg.value_or(0.0), 7.0);
    EXPECT_EQ(failed.max_accuracy_deg, 1.0);
  }
  ASSERT_EQ(events_of(paused.log_path, "session_paused").size(), 1u);

  options.gaze = "synthetic";
  const SessionOutcome resumed = run_session(config, options);
  EXPECT_TRUE(resumed.resumed);
  ASSERT_TRUE(resumed.finished);
  EXPECT_EQ(resumed.trials_completed, resumed.trials_total);
  validations = events_of(resumed.log_path, TrackerValidationEvent::kind);
  ASSERT_EQ(validations.size(), 4u);
  EXPECT_EQ(validations[2]["reason"], "resumed");
  EXPECT_EQ(validations[2]["passed"], true);
  EXPECT_EQ(validations[3]["reason"], "rest");
}

// Log schema 7: the header names the gaze source (its kind, its spec, whether --gaze named it, the
// config's [gaze] require) and the eye-tracker validation the session runs with; a log of an earlier
// schema (without them) is still read, replayed to its hashes, exported and analysed, its source's
// kind told from the `gaze` spec every schema logs (docs/log-schema.md, "Versions").
TEST(SessionGaze, TheHeaderNamesTheSourceAndItsValidationAndAnEarlierSchemaStillReads) {
  const StudyConfig config = validated_config("targets = 5\ntarget_s = 0.5\nsettle_s = 0.2\nmax_accuracy_deg = 0.75\n");
  const fs::path results = fresh_folder("gaze-header");
  const SessionOutcome outcome = run_session(config, simulated(results));
  ASSERT_TRUE(outcome.finished);
  const SessionRecord record = read_session_record(read_event_log(outcome.log_path));
  EXPECT_EQ(record.header.value("schema_version", 0), log_schema_version);
  const nlohmann::json& source = record.header.at("gaze_source");
  EXPECT_EQ(source.value("kind", ""), "synthetic");
  EXPECT_EQ(source.value("spec", ""), record.header.value("gaze", "-"));
  EXPECT_EQ(source.value("spec", "").rfind("synthetic:seed=", 0), 0u);
  EXPECT_EQ(source.value("requested", true), false) << "headless, no --gaze: the default";
  EXPECT_EQ(source.at("require"), nlohmann::json::array());
  const nlohmann::json& validation = record.header.at("gaze_validation");
  EXPECT_EQ(validation.value("enabled", false), true);
  EXPECT_EQ(validation.value("targets", 0), 5);
  EXPECT_DOUBLE_EQ(validation.value("target_s", 0.0), 0.5);
  EXPECT_DOUBLE_EQ(validation.value("settle_s", 0.0), 0.2);
  EXPECT_DOUBLE_EQ(validation.value("max_accuracy_deg", 0.0), 0.75);
  EXPECT_DOUBLE_EQ(validation.value("max_precision_deg", 0.0), 0.5);
  EXPECT_EQ(validation.value("max_attempts", 0), 3);
  EXPECT_EQ(validation.value("after_breaks", false), true);
  // Read back through the typed header, and a study without [validation] says so.
  const SessionHeaderEvent typed = parse_session_header(record.header, FieldCheck::strict);
  EXPECT_EQ(typed.gaze_source, source);
  EXPECT_EQ(typed.gaze_validation, validation);
  SessionOptions named = simulated(fresh_folder("gaze-header-named"));
  named.gaze = "synthetic:seed=5";
  const SessionOutcome plain =
      run_session(parse_study_config_file(study_fixture("tiny_2afc").string(), renderer_scene_catalog()), named);
  const nlohmann::json plain_header = read_session_record(read_event_log(plain.log_path)).header;
  EXPECT_EQ(plain_header.at("gaze_source").value("requested", false), true);
  EXPECT_EQ(plain_header.at("gaze_source").value("spec", ""), "synthetic:seed=5");
  EXPECT_EQ(plain_header.at("gaze_validation"), (nlohmann::json{{"enabled", false}}));
  // The analysis and the export name the source.
  EXPECT_EQ(analysis::load_study({outcome.log_path}).participants.at(0).gaze_source, "synthetic");
  const std::string csv = export_trials_csv({outcome.log_path});
  const std::vector<std::string> rows = testing::lines_of(csv);
  ASSERT_GT(rows.size(), 1u);
  EXPECT_NE(rows.front().find(",gaze_source"), std::string::npos) << rows.front();
  EXPECT_TRUE(rows.front().ends_with(",gaze_source,late_frames")) << rows.front();
  for (size_t i = 1; i < rows.size(); ++i) EXPECT_TRUE(rows[i].ends_with(",synthetic,")) << rows[i];  // no late frames

  // The same session as schema 6 wrote it: no gaze_source, no gaze_validation.
  std::vector<std::string> lines = testing::lines_of(read_file(outcome.log_path));
  nlohmann::json header = nlohmann::json::parse(lines.front());
  header.erase("gaze_source");
  header.erase("gaze_validation");
  header["schema_version"] = 6;
  lines.front() = header.dump();
  const fs::path earlier = results / "schema6" / config.name / "P1" / "events.jsonl";
  fs::create_directories(earlier.parent_path());
  std::ofstream(earlier, std::ios::binary) << testing::rechained(lines);
  const SessionRecord earlier_record = read_session_record(read_event_log(earlier.string()));
  EXPECT_EQ(earlier_record.integrity.status, LogStatus::sealed);
  EXPECT_FALSE(earlier_record.header.contains("gaze_source"));
  const ReplayOutcome replayed = replay(earlier.string());
  EXPECT_EQ(replayed.difference_count, 0) << (replayed.differences.empty() ? "" : replayed.differences.front());
  EXPECT_EQ(replayed.trials, outcome.trials_completed);
  const analysis::StudyData data = analysis::load_study({earlier.string()});
  ASSERT_EQ(data.participants.size(), 1u);
  EXPECT_EQ(data.participants.front().gaze_source, "synthetic") << "told from the header's gaze spec";
  EXPECT_EQ(data.participants.front().validation.attempts, 2);
  const std::vector<std::string> earlier_rows = testing::lines_of(export_trials_csv({earlier.string()}));
  ASSERT_EQ(earlier_rows.size(), rows.size());
  for (size_t i = 1; i < earlier_rows.size(); ++i)
    EXPECT_TRUE(earlier_rows[i].ends_with(",synthetic,")) << earlier_rows[i];  // then late_frames, empty
  // A log of no schema that names its source in a way this build does not know: "not recorded".
  header["gaze"] = "eyelink:1";
  lines.front() = header.dump();
  const fs::path unknown = results / "unknown" / config.name / "P1" / "events.jsonl";
  fs::create_directories(unknown.parent_path());
  std::ofstream(unknown, std::ios::binary) << testing::rechained(lines);
  EXPECT_TRUE(testing::lines_of(export_trials_csv({unknown.string()})).back().ends_with(",not recorded,"));
  // A run resumed with a source of another kind (a trace at the centre) names it in its session_resumed; the session then
  // had both, in the order used.
  const fs::path trace = results / "centre.csv";
  {
    std::ofstream out(trace);
    out << "time_s,x_px,y_px\n";
    for (int i = 0; i < 60 * 60; ++i) out << i / 60.0 << ",32,18\n";
  }
  SessionOptions traced = simulated(results);
  traced.gaze = "trace:" + trace.string();
  const std::string whole = read_file(outcome.log_path);
  const auto [resumed, resumed_log] = resume_after_cut(config, traced, results, whole, whole.size() / 2);
  ASSERT_TRUE(resumed.resumed);  // paused again: the fixed trace fails the validation, which does not matter here
  const SessionRecord resumed_record = read_session_record(read_event_log(resumed_log));
  ASSERT_EQ(resumed_record.resumes.size(), 1u);
  EXPECT_EQ(resumed_record.resumes.front().gaze_source.value("kind", ""), "trace");
  EXPECT_EQ(resumed_record.resumes.front().gaze_source.value("requested", false), true);
  EXPECT_EQ(analysis::load_study({resumed_log}).participants.at(0).gaze_source, "synthetic+trace");
  EXPECT_TRUE(testing::lines_of(export_trials_csv({resumed_log})).back().ends_with(",synthetic+trace,"));
  // This build resumes only its own schema.
  SessionOptions resume = simulated(results / "schema6");
  try {
    run_session(config, resume);
    ADD_FAILURE() << "an earlier schema was resumed";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("log schema 6"), std::string::npos) << error.what();
  }
}

StudyConfig with_practice(const std::string& fixture, const std::string& practice) {
  std::string text = read_file(study_fixture(fixture));
  const std::string from = "inter_trial_s = 0.1";
  text.replace(text.find(from), from.size(), from + "\nrest_between_blocks_s = 1");
  text += "\n[practice]\n" + practice;
  return parse_study_config_text(text, study_fixture(fixture).string(), renderer_scene_catalog());
}

TEST(SessionPractice, PracticeTrialsRunFirstAreLoggedAndExportedButNeverAnalysed) {
  // Issue 18: practice trials (not analysed). 2afc practises the easiest level by default; a ramp
  // practises its whole ladder.
  for (const char* fixture : {"tiny_2afc", "ramp"}) {
    SCOPED_TRACE(fixture);
    const StudyConfig config = with_practice(fixture, "trials = 3\n");
    const StudyConfig without = parse_study_config_file(study_fixture(fixture).string(), renderer_scene_catalog());
    const StudyPlan plan = make_study_plan(config, "P1");
    const StudyPlan plain = make_study_plan(without, "P1");
    ASSERT_EQ(plan.blocks.size(), plain.blocks.size() + 1);
    EXPECT_TRUE(plan.blocks[0].practice);
    EXPECT_EQ(plan.blocks[0].name, "practice");
    EXPECT_EQ(plan.blocks[0].scene, plan.blocks[1].scene);  // the participant's first block's scene
    ASSERT_EQ(plan.trials.size(), plain.trials.size() + 3);
    for (int i = 0; i < 3; ++i) {
      const Trial& trial = plan.trials[size_t(i)];
      EXPECT_TRUE(trial.practice);
      EXPECT_FALSE(trial.attention_check);
      if (std::string(fixture) == "tiny_2afc") EXPECT_EQ(trial.level, 2.0);  // least like the reference
      else EXPECT_EQ(trial.sequence.size(), 5u);                             // four levels and the reference
    }
    // The study's own trials follow, as without practice (conditions and order).
    for (size_t i = 0; i < plain.trials.size(); ++i) {
      EXPECT_FALSE(plan.trials[i + 3].practice);
      EXPECT_EQ(plan.trials[i + 3].condition, plain.trials[i].condition);
    }

    const fs::path results = fresh_folder(std::string("practice-") + fixture);
    SessionOptions options = simulated(results);
    options.screenshots_dir = (results / "shots").string();
    const SessionOutcome outcome = run_session(config, options);
    ASSERT_TRUE(outcome.finished);
    EXPECT_EQ(outcome.trials_completed, int(plan.trials.size()));
    for (const char* kind : {"practice", "practice_end"})
      EXPECT_TRUE(fs::is_regular_file(results / "shots" / (std::string(kind) + ".png"))) << kind;
    const SessionRecord record = read_session_record(read_event_log(outcome.log_path));
    for (const RecordedTrial& trial : record.trials) EXPECT_EQ(trial.start.practice, trial.index < 3) << trial.index;
    // No rest after the practice block; one between the study's two blocks.
    int rests = 0;
    for (const nlohmann::json& event : read_event_log(outcome.log_path).events)
      if (event_kind(event) == "break" && event["reason"] == "rest") ++rests;
    EXPECT_EQ(rests, 1);
    const ReplayOutcome replayed = replay(outcome.log_path);
    EXPECT_EQ(replayed.difference_count, 0) << (replayed.differences.empty() ? "" : replayed.differences.front());

    // Exported with practice = true; the analysis counts them apart and analyses the rest.
    const std::string csv = export_trials_csv({outcome.log_path});
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), outcome.trials_total + 1);
    const analysis::StudyData data = analysis::load_study({outcome.log_path});
    ASSERT_EQ(data.participants.size(), 1u);
    EXPECT_EQ(data.participants[0].practice_trials, 3);
    EXPECT_EQ(data.participants[0].trials.size(), plain.trials.size());
    for (const analysis::StudyTrial& trial : data.participants[0].trials) EXPECT_GE(trial.index, 3);
  }
}

TEST(SessionPractice, ACrashInOrRightAfterThePracticeOrAValidationResumesToTheSameTrials) {
  // Review of issue 18: practice, validation after a rest and after an attention-check break, and a
  // crash anywhere among them. Each cut log resumes (validating again) to the trials of the
  // uninterrupted session.
  std::string text = read_file(study_fixture("tiny_2afc"));
  const std::string from = "inter_trial_s = 0.1";
  text.replace(text.find(from), from.size(), from + "\nrest_between_blocks_s = 1");
  text += "\n[practice]\ntrials = 3\n\n[validation]\ntargets = 5\ntarget_s = 0.3\nsettle_s = 0.1\n";
  const StudyConfig config =
      parse_study_config_text(text, study_fixture("tiny_2afc").string(), renderer_scene_catalog());
  const fs::path results = fresh_folder("practice-resume");
  SessionOptions options = simulated(results / "whole");
  options.observer = "simulated:guess=0.6,seed=3";  // wrong at some attention checks: breaks
  const SessionOutcome whole_run = run_session(config, options);
  ASSERT_TRUE(whole_run.finished);
  const std::vector<std::string> expected = test::trial_summary(whole_run.log_path);
  const std::string whole = read_file(whole_run.log_path);
  std::vector<std::string> reasons;
  std::vector<size_t> cuts;  // after the 2nd and 3rd (last) practice trial, and after each validation
  size_t at = 0;
  for (const nlohmann::json& event : read_event_log(whole_run.log_path).events) {
    at = whole.find('\n', at) + 1;
    const std::string kind = event_kind(event);
    if (kind == TrackerValidationEvent::kind) {
      reasons.push_back(event["reason"]);
      cuts.push_back(at);
    }
    if (kind == "trial_end" && (event["trial"] == 1 || event["trial"] == 2)) cuts.push_back(at);
  }
  EXPECT_EQ(reasons.front(), "start");
  EXPECT_NE(std::find(reasons.begin(), reasons.end(), "rest"), reasons.end());
  EXPECT_NE(std::find(reasons.begin(), reasons.end(), "break"), reasons.end()) << "no validation after a break";
  for (size_t cut : cuts) {
    SCOPED_TRACE("cut at byte " + std::to_string(cut));
    const SessionOutcome resumed = resume_after_cut(config, options, results, whole, cut).first;
    EXPECT_TRUE(resumed.resumed);
    EXPECT_TRUE(resumed.finished);
    EXPECT_EQ(test::trial_summary(resumed.log_path), expected);
    EXPECT_EQ(replay(resumed.log_path).difference_count, 0);
    const SessionRecord record = read_session_record(read_event_log(resumed.log_path));
    ASSERT_FALSE(record.validations.empty());
    EXPECT_EQ(record.validations.back().passed, true);
  }
}

TEST(SessionPractice, BadPracticeTablesNameTheirKey) {
  const auto error_of = [](const std::string& fixture, const std::string& practice) -> std::string {
    try {
      with_practice(fixture, practice);
    } catch (const InputError& error) {
      return error.what();
    }
    return "no error";
  };
  EXPECT_NE(error_of("tiny_2afc", "trials = 2\nlevels = [3]\n")
                .find("practice.levels: expected levels of [levels] values, got 3"),
            std::string::npos);
  EXPECT_NE(error_of("ramp", "trials = 2\nlevels = [2]\n")
                .find("practice.levels: a ramp practice trial shows the whole ladder"),
            std::string::npos);
  EXPECT_NE(error_of("tiny_2afc", "trials = -1\n").find("practice.trials"), std::string::npos);
  EXPECT_NE(
      error_of("tiny_2afc", "trials = 2\nscene = \"nowhere\"\n").find("practice.scene: no built-in scene or file"),
      std::string::npos);
  EXPECT_EQ(error_of("tiny_2afc", "trials = 2\n"), "no error");
  std::string text = read_file(study_fixture("tiny_2afc"));
  text.replace(text.find("name = \"sphere\""), 15, "name = \"practice\"");
  text += "\n[practice]\ntrials = 1\n";
  try {
    parse_study_config_text(text, study_fixture("tiny_2afc").string(), renderer_scene_catalog());
    ADD_FAILURE() << "a block named practice was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("\"practice\" names the [practice] trials' block"), std::string::npos)
        << error.what();
  }
}

TEST(SessionConditions, AConditionsFileRunsReplaysFromTheLogAloneAndAnalysesItsOwnDesign) {
  // Issue 18: conditions from a CSV file (PsychoPy's conditions files). Two variants at levels of
  // their own (not variants x levels): the schedule, the log, replay (with the file gone: the
  // header carries it) and the analysis all follow the file's design.
  const fs::path folder = fresh_folder("conditions");
  fs::create_directories(folder);
  std::string text = read_file(study_fixture("tiny_2afc"));
  const auto replace = [&](const std::string& from, const std::string& to) {
    ASSERT_NE(text.find(from), std::string::npos) << from;
    text.replace(text.find(from), from.size(), to);
  };
  replace("values = [2, 4, 8, 16]\n", "\n[conditions]\nfile = \"conditions.csv\"\n");
  replace(
      "\"../scenes/sphere.glsl\"",
      "\"" + (study_fixture("tiny_2afc").parent_path() / "../scenes/sphere.glsl").lexically_normal().string() + "\"");
  std::ofstream(folder / "study.toml", std::ios::binary) << text;
  std::ofstream(folder / "conditions.csv", std::ios::binary) << "variant,max_steps,min_filter_size\n"
                                                                "coarse,2,1\ncoarse,4,1\nfine,8,5\nfine,16,5\n";
  const StudyConfig config = parse_study_config_file((folder / "study.toml").string(), renderer_scene_catalog());
  const SessionOutcome outcome = run_session(config, simulated(folder / "results"));
  ASSERT_TRUE(outcome.finished);
  const SessionRecord record = read_session_record(read_event_log(outcome.log_path));
  EXPECT_EQ(record.header.value("conditions_csv", ""), read_file(folder / "conditions.csv"));
  std::set<std::string> conditions;
  for (const RecordedTrial& trial : record.trials)
    if (!trial.start.attention_check) conditions.insert(trial.start.condition);
  EXPECT_EQ(conditions, (std::set<std::string>{"coarse/level=2", "coarse/level=4", "fine/level=16", "fine/level=8"}));

  fs::remove(folder / "conditions.csv");
  const ReplayOutcome replayed = replay(outcome.log_path);
  EXPECT_EQ(replayed.difference_count, 0) << (replayed.differences.empty() ? "" : replayed.differences.front());
  EXPECT_EQ(replayed.trials, outcome.trials_total);

  const analysis::StudyData data = analysis::load_study({outcome.log_path});
  analysis::AnalysisOptions analysis_options;
  analysis_options.bootstrap_samples = 0;
  const analysis::AnalysisResult result = analysis::analyse_study(data, analysis_options);
  for (const analysis::LeftOut& left : result.left_out)
    EXPECT_EQ(left.reason.find("no trial of an included participant"), std::string::npos)
        << left.what << ": " << left.reason;
  std::vector<std::string> rows;
  for (const analysis::ConditionRow& row : result.conditions)
    if (row.level) rows.push_back(row.group.scene + "|" + row.group.variant + "|" + row.condition);
  // The two blocks and their pool ("all"), each with the file's four conditions and no other.
  EXPECT_EQ(rows.size(), 3u * 4u) << ::testing::PrintToString(rows);
  const std::string csv = export_trials_csv({outcome.log_path});
  EXPECT_NE(csv.find("fine/level=16"), std::string::npos);
}

}  // namespace
}  // namespace fovlab

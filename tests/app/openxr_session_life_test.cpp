// A headset session's life at the command line (issue 42, docs/hmd.md): the focus lost and given
// back within one run (the paused, sealed session resumes as a rerun would), the runtime stopping
// the session for good (sealed, exits; the next run resumes), the runtime stopping it and offering
// READY again (resumed in the same run) or not within the timeout, Ctrl-C while the paused session
// waits (sealed, exits as a closed window's run does), late frames counted in the stimulus events
// they belong to, and a log of schema 11 (before late frames) still read and replayed. The test runtime
// (tests/xr_runtime) runs in the child process, scripted by its FOVLAB_TEST_XR_* switches, with the
// OpenXR core validation layer on (its file must stay empty).
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/csv.h"
#include "study/log/event_log.h"
#include "tests/app/cli_test_support.h"
#include "tests/app/headset_study_support.h"

namespace fovlab {
namespace {

using cli_test::CommandResult;

const std::string kSimulated = " --observer simulated --gaze synthetic:seed=3";

std::vector<nlohmann::json> read_events(const std::filesystem::path& log) {
  std::vector<nlohmann::json> events;
  std::ifstream lines(log);
  for (std::string line; std::getline(lines, line);) events.push_back(nlohmann::json::parse(line));
  return events;
}

std::vector<std::string> kinds_of(const std::vector<nlohmann::json>& events) {
  std::vector<std::string> kinds;
  for (const nlohmann::json& event : events) kinds.push_back(event.value("event", ""));
  return kinds;
}

// trials.csv of the logs under `folder` (fovlab export), each row by its header's names.
std::vector<std::map<std::string, std::string>> exported_trials(const std::filesystem::path& folder,
                                                                const std::filesystem::path& out) {
  const cli_test::CommandResult exported = cli_test::run("export " + folder.string() + " --out " + out.string());
  EXPECT_EQ(exported.exit_code, 0) << exported.err;
  std::ifstream file(out);
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const std::vector<CsvRow> rows = read_csv_rows(text, out.string());
  std::vector<std::map<std::string, std::string>> trials;
  if (rows.empty()) return trials;
  EXPECT_EQ(rows.front().cells.back(), "late_frames") << "the last column";
  for (size_t r = 1; r < rows.size(); ++r) {
    std::map<std::string, std::string> trial;
    for (size_t c = 0; c < rows[r].cells.size() && c < rows.front().cells.size(); ++c)
      trial[rows.front().cells[c]] = rows[r].cells[c];
    trials.push_back(trial);
  }
  return trials;
}

// What two runs of the same session must agree on, trial by trial, whatever happened between them:
// each complete trial's start (condition, level, sequence, order), the stimuli it showed, and the
// answers given. Times and gaze-dependent frames are left out (the session clock goes on through a
// pause, and the synthetic gaze follows it).
std::vector<nlohmann::json> complete_trials(const std::vector<nlohmann::json>& events) {
  std::vector<nlohmann::json> trials;
  nlohmann::json open;
  for (const nlohmann::json& event : events) {
    const std::string kind = event.value("event", "");
    if (kind == "trial_start") {
      open = {{"trial", event["trial"]},
              {"condition", event["condition"]},
              {"level", event.value("level", nlohmann::json())},
              {"sequence", event["sequence"]},
              {"reference_first", event.value("reference_first", nlohmann::json())},
              {"stimuli", nlohmann::json::array()},
              {"answers", nlohmann::json::array()}};
    } else if (kind == "stimulus" && !open.is_null()) {
      open["stimuli"].push_back(event["stimulus"]);
    } else if (kind == "response" && !open.is_null()) {
      open["answers"].push_back(event["answer"]);
    } else if (kind == "trial_end" && !open.is_null()) {
      trials.push_back(open);
      open = nullptr;
    } else if (kind == "session_paused") {
      open = nullptr;  // cut: the resumed session discards it and presents it again
    }
  }
  return trials;
}

// The frame (the session's xrWaitFrame count) whose predicted display time a present_s of a new
// session's log is: the first frame is at 0, one frame each 1/90 s.
int64_t frame_of_present(double present_s) { return std::llround(present_s * 90.0) + 1; }

// The kinds of the log's events from its last session_paused on (empty when there is none).
std::vector<std::string> kinds_from_last_pause(const std::vector<std::string>& kinds) {
  const auto last = std::find(kinds.rbegin(), kinds.rend(), "session_paused");
  return last == kinds.rend() ? std::vector<std::string>{} : std::vector<std::string>(last.base() - 1, kinds.end());
}

// The test runtime's own complaints (a call refused because the product made it in the wrong state).
bool runtime_complained(const std::string& err) { return err.find("fovlab test runtime:") != std::string::npos; }

class HeadsetSessionLife : public test::HeadsetStudy {
 protected:
  // The complete trials of the same participant's session run without any interruption, in a
  // results folder of its own.
  std::vector<nlohmann::json> uninterrupted_trials(const std::filesystem::path& config) {
    const std::filesystem::path results = scratch_.path() / "uninterrupted";
    const CommandResult ran =
        cli_test::run("run " + config.string() + " --participant P01 --results " + results.string() + kSimulated,
                      child_environment(FOVLAB_TEST_XR_RUNTIME_JSON));
    EXPECT_EQ(ran.exit_code, 0) << ran.err;
    return complete_trials(read_events(results / "headset_cli" / "P01" / "events.jsonl"));
  }
  // The log's trials are the two of that uninterrupted run.
  void expect_the_trials_of_an_uninterrupted_run(const std::filesystem::path& config,
                                                 const std::vector<nlohmann::json>& events) {
    const std::vector<nlohmann::json> expected = uninterrupted_trials(config);
    ASSERT_EQ(expected.size(), 2u);
    EXPECT_EQ(complete_trials(events), expected);
  }
};

// `fovlab replay --verify` renders the log's every frame again and finds each hash.
void expect_replay_matches(const std::filesystem::path& log) {
  const CommandResult replayed = cli_test::run("replay " + log.string() + " --verify");
  EXPECT_EQ(replayed.exit_code, 0) << replayed.out << replayed.err;
  EXPECT_NE(replayed.out.find("replay matches the log"), std::string::npos) << replayed.out;
}

// The headset taken off at frame 400 and put back on at frame 700: the study pauses as before
// (session_paused, sealed), the "Paused" screen keeps the runtime's frames coming, and when the focus
// returns the session resumes in the same run (session_resumed after the seal, the cut trial
// discarded), to the end: the trials are those of an uninterrupted run of the same session, and
// the log replays both eyes to their hashes.
TEST_F(HeadsetSessionLife, TheFocusBackWithinTheTimeoutResumesTheSessionInTheSameRun) {
  const std::filesystem::path config = write("a.toml", test::headset_study(test::kEyesAtDistance));
  const CommandResult ran = run_study(config, "FOVLAB_TEST_XR_UNFOCUS_AT_FRAME=400 FOVLAB_TEST_XR_REFOCUS_AT_FRAME=700",
                                      FOVLAB_TEST_XR_RUNTIME_JSON, kSimulated);
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  EXPECT_NE(ran.out.find("new session, 2 of 2 trials complete"), std::string::npos) << ran.out;
  EXPECT_EQ(ran.out.find("paused after"), std::string::npos) << ran.out;
  EXPECT_NE(ran.out.find("the focus was lost and came back 1 time(s)"), std::string::npos) << ran.out;
  EXPECT_NE(ran.err.find("the headset is focused again: the session resumes"), std::string::npos) << ran.err;

  const std::filesystem::path log = results_ / "headset_cli" / "P01" / "events.jsonl";
  const std::vector<nlohmann::json> events = read_events(log);
  const std::vector<std::string> kinds = kinds_of(events);
  const auto paused = std::find(kinds.begin(), kinds.end(), "session_paused");
  ASSERT_NE(paused, kinds.end()) << "no session_paused";
  const size_t paused_at = static_cast<size_t>(paused - kinds.begin());
  ASSERT_LT(paused_at + 3, kinds.size());
  EXPECT_EQ(kinds[paused_at + 1], "seal");
  EXPECT_EQ(kinds[paused_at + 2], "session_resumed");
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "session_paused"), 1);
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "session_resumed"), 1);
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "session_end"), 1);
  EXPECT_EQ(kinds.back(), "seal");
  const nlohmann::json& pause = events[paused_at];
  const nlohmann::json& resumed = events[paused_at + 2];
  EXPECT_NE(pause.value("reason", "").find("lost focus (XR_SESSION_STATE_VISIBLE)"), std::string::npos) << pause;
  // Resumed after the focus came back at frame 700 (its display time on the session clock), in
  // this run: the paused session waited for it.
  EXPECT_LT(pause["t"].get<double>(), 699.0 / 90.0) << pause;
  EXPECT_GE(resumed["t"].get<double>(), 699.0 / 90.0 - 1e-6) << resumed;
  // Where the pause cut a trial (a trial_start without its trial_end), the resumed session names it
  // as discarded, and starts again from it.
  int cut_trial = -1;
  for (size_t i = 0; i < paused_at; ++i) {
    if (kinds[i] == "trial_start") cut_trial = events[i]["trial"].get<int>();
    if (kinds[i] == "trial_end") cut_trial = -1;
  }
  if (cut_trial >= 0) {
    EXPECT_EQ(resumed.value("discarded_trial", -1), cut_trial) << resumed;
    EXPECT_EQ(resumed.value("next_trial", -1), cut_trial) << resumed;
  } else {
    EXPECT_FALSE(resumed.contains("discarded_trial")) << resumed;
  }
  // The resumed part begins as a rerun's does: the instructions screen that says so, answered.
  EXPECT_EQ(kinds[paused_at + 3], "instructions");

  expect_replay_matches(log);

  // The same participant's session, never interrupted, in another results folder.
  expect_the_trials_of_an_uninterrupted_run(config, events);
}

// The runtime stopping the session (FOVLAB_TEST_XR_STOP_AT_FRAME: STOPPING, as a runtime shutting
// down): no focus can come back, so the session pauses, seals and exits at once; the next run
// resumes it to the end.
TEST_F(HeadsetSessionLife, TheRuntimeStoppingTheSessionSealsItAndTheNextRunResumes) {
  const std::filesystem::path config = write("a.toml", test::headset_study(test::kEyesAtDistance));
  const CommandResult stopped =
      run_study(config, "FOVLAB_TEST_XR_STOP_AT_FRAME=400", FOVLAB_TEST_XR_RUNTIME_JSON, kSimulated);
  ASSERT_EQ(stopped.exit_code, 0) << stopped.err;
  EXPECT_NE(stopped.out.find("paused after"), std::string::npos) << stopped.out;
  EXPECT_EQ(stopped.err.find("waiting up to"), std::string::npos) << "a stopped session has no focus to wait for";
  const std::filesystem::path log = results_ / "headset_cli" / "P01" / "events.jsonl";
  std::vector<nlohmann::json> events = read_events(log);
  std::vector<std::string> kinds = kinds_of(events);
  ASSERT_GE(kinds.size(), 3u);
  EXPECT_EQ(kinds[kinds.size() - 2], "session_paused");
  EXPECT_NE(events[kinds.size() - 2].value("reason", "").find("the headset session ended"), std::string::npos)
      << events[kinds.size() - 2];
  EXPECT_EQ(kinds.back(), "seal");
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "session_resumed"), 0);

  const CommandResult resumed = run_study(config, "", FOVLAB_TEST_XR_RUNTIME_JSON, kSimulated);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("resumed, 2 of 2 trials complete"), std::string::npos) << resumed.out;
  kinds = kinds_of(read_events(log));
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "session_resumed"), 1);
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "session_end"), 1);
  const CommandResult replayed = cli_test::run("replay " + log.string() + " --verify");
  EXPECT_EQ(replayed.exit_code, 0) << replayed.out << replayed.err;
}

// The runtime stopping the session at frame 400 as its own pause (its home screen, a proximity
// sensor: STOPPING without EXITING) and offering READY again 30 empty polls after the product ended
// the session: the study pauses and seals as for a lost focus, the product ends the session and
// polls without a frame loop (the test runtime refuses xrWaitFrame, xrBeginSession and input reads in
// the wrong state, which would fail the run), begins it again at READY, runs frames to FOCUSED and
// resumes in the same run: one pause, one resume, the trials of an uninterrupted run, replayed to
// their hashes.
TEST_F(HeadsetSessionLife, TheRuntimeStoppingAndOfferingReadyAgainResumesTheSessionInTheSameRun) {
  const std::filesystem::path config = write("a.toml", test::headset_study(test::kEyesAtDistance));
  const CommandResult ran =
      run_study(config, "FOVLAB_TEST_XR_STOP_AT_FRAME=400 FOVLAB_TEST_XR_READY_AGAIN_AFTER_POLLS=30",
                FOVLAB_TEST_XR_RUNTIME_JSON, kSimulated);
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  EXPECT_FALSE(runtime_complained(ran.err)) << ran.err;
  EXPECT_NE(ran.out.find("new session, 2 of 2 trials complete"), std::string::npos) << ran.out;
  EXPECT_EQ(ran.out.find("paused after"), std::string::npos) << ran.out;
  EXPECT_NE(ran.out.find("the focus was lost and came back 1 time(s)"), std::string::npos) << ran.out;
  EXPECT_NE(ran.err.find("waiting up to"), std::string::npos) << ran.err;
  EXPECT_NE(ran.err.find("the headset is focused again: the session resumes"), std::string::npos) << ran.err;

  const std::filesystem::path log = results_ / "headset_cli" / "P01" / "events.jsonl";
  const std::vector<nlohmann::json> events = read_events(log);
  const std::vector<std::string> kinds = kinds_of(events);
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "session_paused"), 1);
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "session_resumed"), 1);
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "session_end"), 1);
  EXPECT_EQ(kinds.back(), "seal");
  const size_t paused_at = static_cast<size_t>(std::find(kinds.begin(), kinds.end(), "session_paused") - kinds.begin());
  ASSERT_LT(paused_at + 3, kinds.size());
  EXPECT_EQ(kinds[paused_at + 1], "seal");
  EXPECT_EQ(kinds[paused_at + 2], "session_resumed");
  EXPECT_EQ(kinds[paused_at + 3], "instructions");
  EXPECT_NE(events[paused_at].value("reason", "").find("stopped the headset session"), std::string::npos)
      << events[paused_at];
  // Stopped at frame 400: paused before it is displayed, resumed after it (the session clock goes on).
  EXPECT_LT(events[paused_at]["t"].get<double>(), 400.0 / 90.0) << events[paused_at];
  EXPECT_GT(events[paused_at + 2]["t"].get<double>(), events[paused_at]["t"].get<double>());

  expect_replay_matches(log);

  expect_the_trials_of_an_uninterrupted_run(config, events);
}

// The runtime stopping the session and not offering READY again within --refocus-timeout: the
// paused, sealed session waits (polling, no frames) for the timeout, then exits as a session the
// runtime ended does; the next run resumes it to the end.
TEST_F(HeadsetSessionLife, TheRuntimeStoppingWithoutReadyAgainWithinTheTimeoutSealsAndTheNextRunResumes) {
  const std::filesystem::path config = write("a.toml", test::headset_study(test::kEyesAtDistance));
  const auto start = std::chrono::steady_clock::now();
  const CommandResult stopped =
      run_study(config, "FOVLAB_TEST_XR_STOP_AT_FRAME=400 FOVLAB_TEST_XR_READY_AGAIN_AFTER_POLLS=never",
                FOVLAB_TEST_XR_RUNTIME_JSON, kSimulated + " --refocus-timeout 1");
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(stopped.exit_code, 0) << stopped.err;
  EXPECT_FALSE(runtime_complained(stopped.err)) << stopped.err;
  EXPECT_NE(stopped.out.find("paused after"), std::string::npos) << stopped.out;
  EXPECT_NE(stopped.err.find("waiting up to 1 s"), std::string::npos) << stopped.err;
  EXPECT_NE(stopped.err.find("the headset was not focused again; the session stays paused"), std::string::npos)
      << stopped.err;
  EXPECT_GE(wall_s, 1.0) << "the stopped session's wait is counted on the wall clock";
  const std::filesystem::path log = results_ / "headset_cli" / "P01" / "events.jsonl";
  std::vector<nlohmann::json> events = read_events(log);
  std::vector<std::string> kinds = kinds_of(events);
  EXPECT_EQ(kinds_from_last_pause(kinds), (std::vector<std::string>{"session_paused", "seal"}));
  ASSERT_GE(events.size(), 2u);
  EXPECT_NE(events[events.size() - 2].value("reason", "").find("stopped the headset session"), std::string::npos)
      << events[events.size() - 2];
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "session_resumed"), 0);

  const CommandResult resumed = run_study(config, "", FOVLAB_TEST_XR_RUNTIME_JSON, kSimulated);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("resumed, 2 of 2 trials complete"), std::string::npos) << resumed.out;
  kinds = kinds_of(read_events(log));
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "session_resumed"), 1);
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "session_end"), 1);
  expect_replay_matches(log);
}

// Ctrl-C at the terminal while the paused session waits for a focus that does not come (taken off
// at frame 400, never put back on; the default --refocus-timeout of 10 minutes): SIGINT is sent to
// the `fovlab run` process as soon as its log shows session_paused. The run ends as a run whose
// window was closed does (exit 0, "paused after", the log ending in the pause and its seal, intact),
// and the next run resumes it to the end, replayed to its hashes.
TEST_F(HeadsetSessionLife, CtrlCWhileThePausedSessionWaitsEndsTheRunSealedAndTheNextRunResumes) {
  const std::filesystem::path config = write("a.toml", test::headset_study(test::kEyesAtDistance));
  const std::filesystem::path log = results_ / "headset_cli" / "P01" / "events.jsonl";
  const std::filesystem::path out = scratch_.path() / "run.out", err = scratch_.path() / "run.err";
  // `exec`: the shell becomes env, which becomes fovlab, so the child's pid is fovlab's and SIGINT
  // reaches it alone (a foreground command, so SIGINT is not ignored as in a background job).
  const std::string command = "exec " + child_environment(FOVLAB_TEST_XR_RUNTIME_JSON) +
                              " FOVLAB_TEST_XR_UNFOCUS_AT_FRAME=400 " + FOVLAB_BINARY + " run " + config.string() +
                              " --participant P01 --results " + results_.string() + kSimulated + " >" + out.string() +
                              " 2>" + err.string();
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  bool paused = false;
  int status = 0;
  bool exited = false;
  for (int waited_ms = 0; waited_ms < 180000 && !paused; waited_ms += 20) {
    if (waitpid(child, &status, WNOHANG) == child) {
      exited = true;
      break;
    }
    paused = cli_test::read_all(log).find("\"session_paused\"") != std::string::npos;
    if (!paused) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (paused) kill(child, SIGINT);
  if (!exited) {
    if (!paused) kill(child, SIGKILL);  // never paused: do not leave it running
    ASSERT_EQ(waitpid(child, &status, 0), child);
  }
  ASSERT_TRUE(paused) << "no session_paused in the log; stderr: " << cli_test::read_all(err);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0)
                                 << "; stderr: " << cli_test::read_all(err);
  EXPECT_EQ(WEXITSTATUS(status), 0) << cli_test::read_all(err);
  const std::string printed = cli_test::read_all(out), complained = cli_test::read_all(err);
  EXPECT_NE(printed.find("paused after"), std::string::npos) << printed;
  EXPECT_NE(complained.find("ended at the terminal"), std::string::npos) << complained;
  EXPECT_FALSE(runtime_complained(complained)) << complained;
  const std::vector<nlohmann::json> events = read_events(log);  // each line parses: none torn
  const std::vector<std::string> kinds = kinds_of(events);
  EXPECT_EQ(kinds_from_last_pause(kinds), (std::vector<std::string>{"session_paused", "seal"}));
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "session_resumed"), 0);

  const CommandResult resumed = run_study(config, "", FOVLAB_TEST_XR_RUNTIME_JSON, kSimulated);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("resumed, 2 of 2 trials complete"), std::string::npos) << resumed.out;
  EXPECT_EQ(resumed.err.find("torn"), std::string::npos) << resumed.err;
  expect_replay_matches(log);
}

// The test runtime makes every 4th of the first 300 frames late (FOVLAB_TEST_XR_LATE_AT_FRAMES: its
// virtual clock is past the frame's display time at xrEndFrame): each stimulus event counts exactly
// its refreshes among them (found from present_s, the frames' predicted display times), and 0 where
// none is; `run` prints the total beside the dropped frames. A runtime without
// XR_KHR_convert_timespec_time measures nothing: no late_frames, and the header says so.
TEST_F(HeadsetSessionLife, LateFramesAreCountedInTheStimulusEventsTheyBelongTo) {
  std::set<int64_t> late;
  std::string late_setting;
  for (int64_t frame = 4; frame <= 300; frame += 4) {
    late.insert(frame);
    late_setting += (late_setting.empty() ? "" : ",") + std::to_string(frame);
  }
  const std::filesystem::path config = write("a.toml", test::headset_study(test::kEyesAtDistance));
  const CommandResult ran =
      run_study(config, "FOVLAB_TEST_XR_LATE_AT_FRAMES=" + late_setting, FOVLAB_TEST_XR_RUNTIME_JSON, kSimulated);
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  const std::filesystem::path log = results_ / "headset_cli" / "P01" / "events.jsonl";
  const std::vector<nlohmann::json> events = read_events(log);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.front().value("schema_version", 0), log_schema_version);
  EXPECT_EQ(events.front()["headset"].value("late_frames_measured", false), true) << events.front()["headset"];
  int stimuli = 0, with_late = 0, without_late = 0, total_late = 0;
  std::map<int, int> late_of_trial;  // the trial's stimulus events' late_frames, summed
  for (const nlohmann::json& event : events) {
    if (event.value("event", "") != "stimulus") continue;
    ++stimuli;
    late_of_trial[event["trial"].get<int>()] += event.value("late_frames", 0);
    ASSERT_TRUE(event.contains("late_frames")) << event;
    int expected = 0;
    for (const nlohmann::json& present_s : event["present_s"])
      expected += late.count(frame_of_present(present_s.get<double>())) ? 1 : 0;
    EXPECT_EQ(event["late_frames"].get<int>(), expected) << event["present_s"];
    EXPECT_EQ(event.value("dropped_frames", -1), 0) << "late is not dropped";
    (expected > 0 ? with_late : without_late) += 1;
    total_late += event["late_frames"].get<int>();
  }
  EXPECT_EQ(stimuli, 4);
  EXPECT_GT(with_late, 0) << "no stimulus was shown in the first 300 frames";
  EXPECT_GT(without_late, 0) << "every stimulus was shown in the first 300 frames";
  EXPECT_NE(ran.out.find(", " + std::to_string(total_late) + " late"), std::string::npos) << ran.out;
  // The analysis counts them from the log (thresholds.json's participant headset; report.html's table).
  const std::filesystem::path report = scratch_.path() / "report";
  const CommandResult analysed =
      cli_test::run("analyze " + (results_ / "headset_cli").string() + " --out " + report.string());
  ASSERT_EQ(analysed.exit_code, 0) << analysed.err;
  std::ifstream thresholds_file(report / "thresholds.json");
  const nlohmann::json thresholds = nlohmann::json::parse(thresholds_file);
  EXPECT_EQ(thresholds["participants"][0]["headset"].value("late_frames", -1), total_late) << thresholds["participants"];
  // trials.csv's last column: each trial's late frames (0 where it had none: measured).
  const auto trials = exported_trials(results_ / "headset_cli", scratch_.path() / "trials.csv");
  ASSERT_EQ(trials.size(), late_of_trial.size());
  int exported_late = 0;
  for (const auto& trial : trials) {
    const int index = std::stoi(trial.at("trial"));
    EXPECT_EQ(trial.at("late_frames"), std::to_string(late_of_trial.at(index))) << "trial " << index;
    exported_late += std::stoi(trial.at("late_frames"));
  }
  EXPECT_EQ(exported_late, total_late);

  const std::filesystem::path unmeasured_results = scratch_.path() / "unmeasured";
  const CommandResult unmeasured = cli_test::run(
      "run " + config.string() + " --participant P01 --results " + unmeasured_results.string() + kSimulated,
      child_environment(FOVLAB_TEST_XR_RUNTIME_JSON) +
          " FOVLAB_TEST_XR_CONVERT_TIMESPEC=absent FOVLAB_TEST_XR_LATE_AT_FRAMES=" + late_setting);
  ASSERT_EQ(unmeasured.exit_code, 0) << unmeasured.err;
  const std::vector<nlohmann::json> unmeasured_events =
      read_events(unmeasured_results / "headset_cli" / "P01" / "events.jsonl");
  ASSERT_FALSE(unmeasured_events.empty());
  EXPECT_EQ(unmeasured_events.front()["headset"].value("late_frames_measured", true), false);
  for (const nlohmann::json& event : unmeasured_events) EXPECT_FALSE(event.contains("late_frames")) << event;
  EXPECT_EQ(unmeasured.out.find(" late"), std::string::npos) << unmeasured.out;
  const std::filesystem::path unmeasured_report = scratch_.path() / "unmeasured_report";
  ASSERT_EQ(cli_test::run("analyze " + (unmeasured_results / "headset_cli").string() + " --out " +
                          unmeasured_report.string())
                .exit_code,
            0);
  std::ifstream unmeasured_thresholds_file(unmeasured_report / "thresholds.json");
  const nlohmann::json unmeasured_thresholds = nlohmann::json::parse(unmeasured_thresholds_file);
  EXPECT_TRUE(unmeasured_thresholds["participants"][0]["headset"]["late_frames"].is_null()) << "not measured, not 0";
  const auto unmeasured_trials =
      exported_trials(unmeasured_results / "headset_cli", scratch_.path() / "unmeasured_trials.csv");
  EXPECT_FALSE(unmeasured_trials.empty());
  for (const auto& trial : unmeasured_trials) EXPECT_EQ(trial.at("late_frames"), "") << "not measured, not 0";
}

// A headset log as schema 11 wrote it (no late_frames, no headset.late_frames_measured; its chain
// and seals made anew, as that build made them): it reads, replays both eyes to their hashes, and
// exports, as before.
TEST_F(HeadsetSessionLife, AHeadsetLogOfSchema11StillReadsAndReplays) {
  const std::filesystem::path config = write("a.toml", test::headset_study(test::kEyesAtDistance));
  const CommandResult ran =
      run_study(config, "FOVLAB_TEST_XR_LATE_AT_FRAMES=20,40,60", FOVLAB_TEST_XR_RUNTIME_JSON, kSimulated);
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  const std::filesystem::path log = results_ / "headset_cli" / "P01" / "events.jsonl";
  const std::filesystem::path old_log = scratch_.path() / "schema11" / "headset_cli" / "P01" / "events.jsonl";
  std::filesystem::create_directories(old_log.parent_path());
  {
    std::ofstream out(old_log, std::ios::binary);
    std::string chain;
    int stripped = 0;
    for (nlohmann::json event : read_events(log)) {
      event.erase("chain");
      if (event.value("event", "") == "session_header") {
        event["schema_version"] = 11;
        stripped += static_cast<int>(event["headset"].erase("late_frames_measured"));
      }
      stripped += static_cast<int>(event.erase("late_frames"));
      event.erase("right_eye_invalid_gaze");  // schema 13
      if (event.value("event", "") == "seal") event["last_chain"] = chain;
      chain = event_chain(chain, event, 11);
      event["chain"] = chain;
      out << event.dump() << '\n';
    }
    EXPECT_GT(stripped, 4) << "the header's and every stimulus event's schema-12 fields";
  }
  expect_replay_matches(old_log);
  const CommandResult exported =
      cli_test::run("export " + old_log.string() + " --out " + (scratch_.path() / "trials.csv").string());
  EXPECT_EQ(exported.exit_code, 0) << exported.out << exported.err;
  // Before schema 13 the right eye's own invalid gaze was not marked: its off-image share is unknown.
  const std::filesystem::path report = scratch_.path() / "report11";
  const CommandResult analyzed =
      cli_test::run("analyze " + (scratch_.path() / "schema11" / "headset_cli").string() + " --out " + report.string());
  ASSERT_EQ(analyzed.exit_code, 0) << analyzed.out << analyzed.err;
  std::ifstream thresholds(report / "thresholds.json");
  const nlohmann::json eyes = nlohmann::json::parse(thresholds)["participants"][0]["headset"]["eyes"];
  EXPECT_TRUE(eyes[1]["gaze_off_image_share"].is_null()) << eyes;
  EXPECT_FALSE(eyes[0]["gaze_off_image_share"].is_null()) << eyes;
}

// --refocus-timeout takes seconds >= 0: anything else is refused in one line, before the runtime is
// asked for anything or a results folder exists.
TEST_F(HeadsetSessionLife, ARefocusTimeoutBelowZeroIsRefusedInOneLine) {
  const std::filesystem::path config = write("a.toml", test::headset_study(test::kEyesAtDistance));
  cli_test::expect_one_line_error(
      run_study(config, "", FOVLAB_TEST_XR_RUNTIME_JSON, kSimulated + " --refocus-timeout -1"),
      "--refocus-timeout -1.000000: expected seconds >= 0");
  EXPECT_FALSE(std::filesystem::exists(results_));
}

}  // namespace
}  // namespace fovlab

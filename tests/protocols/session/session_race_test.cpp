// Issue 14: two `fovlab run` of one participant. Each race is lined up exactly with the test-only
// pause points (core/test_pause.h): the first process stops itself at a phase (SIGSTOP), the
// second runs in full, then the first continues. The participant's lock, taken before anything is
// read, makes the second change nothing and exit 2 naming the first; the first then finishes a
// whole, single session.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "protocols/stimuli/stimulus_settings.h"
#include "core/input_error.h"
#include "study/log/log_integrity.h"
#include "protocols/session/replay.h"
#include "protocols/session/session.h"
#include "tests/protocols/session/session_test_support.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;

struct Child {
  pid_t pid = -1;
  fs::path output;  // stdout and stderr
};

// `fovlab run` of the pair fixture for participant R1; `pause_at`: a pause point, or "".
Child start_run(const fs::path& results, const std::string& pause_at, const std::string& name) {
  Child child;
  child.output = results.parent_path() / (name + "-output.txt");
  const std::string config = test::study_fixture("pair").string();
  const std::string results_text = results.string();
  child.pid = fork();
  if (child.pid == 0) {
    if (pause_at.empty()) ::unsetenv("FOVLAB_TEST_PAUSE_AT");
    else ::setenv("FOVLAB_TEST_PAUSE_AT", pause_at.c_str(), 1);
    freopen(child.output.c_str(), "w", stdout);
    freopen(child.output.c_str(), "a", stderr);
    execl(FOVLAB_BINARY, FOVLAB_BINARY, "run", config.c_str(), "--participant", "R1", "--observer", "simulated",
          "--headless", "--results", results_text.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return child;
}

// Waits until the child has stopped itself at its pause point.
bool wait_until_stopped(pid_t pid, double limit_s = 300.0) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(limit_s);
  while (std::chrono::steady_clock::now() < deadline) {
    int status = 0;
    const pid_t got = waitpid(pid, &status, WNOHANG | WUNTRACED);
    if (got == pid) return WIFSTOPPED(status);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

int exit_code(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int count_of(const std::string& text, const std::string& needle) {
  int count = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++count;
  return count;
}

void expect_one_whole_session(const std::string& log_path) {
  const std::string text = test::read_file(log_path);
  EXPECT_EQ(count_of(text, "\"event\":\"session_header\""), 1);
  const SessionRecord record = read_session_record(read_event_log(log_path));
  EXPECT_TRUE(record.ended);
  EXPECT_EQ(record.integrity.status, LogStatus::sealed) << record.integrity.describe();
  ReplayOptions replay;
  replay.log_path = log_path;
  replay.validation = true;
  EXPECT_EQ(replay_session(replay).difference_count, 0);
}

// Before: run A checked that no log existed, then spent seconds preparing stimuli; run B, started
// in that window, also saw no log, so both wrote a session into one file (two headers, seq from 0).
TEST(SessionRace, ASecondRunDuringTheFirstsPreparationChangesNothing) {
  const fs::path root = test::fresh_folder("race-new");
  const fs::path results = root / "results";
  const std::string log_path = session_log_path(results.string(), "tiny_pair", "R1");
  const Child first = start_run(results, "prepared", "first");
  ASSERT_TRUE(wait_until_stopped(first.pid)) << test::read_file(first.output);
  const Child second = start_run(results, "", "second");
  EXPECT_EQ(exit_code(second.pid), 2) << test::read_file(second.output);
  const std::string refused = test::read_file(second.output);
  EXPECT_NE(refused.find("another fovlab process runs this participant (pid " + std::to_string(first.pid)),
            std::string::npos)
      << refused;
  EXPECT_FALSE(fs::exists(log_path));  // the first has not written yet, and the second wrote nothing
  kill(first.pid, SIGCONT);
  EXPECT_EQ(exit_code(first.pid), 0) << test::read_file(first.output);
  expect_one_whole_session(log_path);
}

// Before: run B set a torn last line aside and truncated the log from what it had read, before it
// took the lock, while run A was appending: A's events were cut. Now the lock comes first.
TEST(SessionRace, ASecondRunCannotCutALogWithATornTailThatTheFirstResumes) {
  const fs::path root = test::fresh_folder("race-torn");
  // A whole session, then its first part with half a line after it (what a crash leaves).
  const fs::path whole_results = root / "whole";
  const Child whole = start_run(whole_results, "", "whole");
  ASSERT_EQ(exit_code(whole.pid), 0) << test::read_file(whole.output);
  const std::string whole_log = session_log_path(whole_results.string(), "tiny_pair", "R1");
  const std::string text = test::read_file(whole_log);
  const size_t cut = text.find('\n', text.size() / 3) + 1 + 25;

  const fs::path results = root / "results";
  const std::string log_path = session_log_path(results.string(), "tiny_pair", "R1");
  fs::create_directories(fs::path(log_path).parent_path());
  std::ofstream(log_path, std::ios::binary) << text.substr(0, cut);
  const Child first = start_run(results, "locked", "first");
  ASSERT_TRUE(wait_until_stopped(first.pid)) << test::read_file(first.output);
  const Child second = start_run(results, "", "second");
  EXPECT_EQ(exit_code(second.pid), 2) << test::read_file(second.output);
  EXPECT_EQ(test::read_file(log_path), text.substr(0, cut));  // untouched: torn tail still there
  EXPECT_FALSE(fs::exists(log_path + ".torn-1"));
  kill(first.pid, SIGCONT);
  EXPECT_EQ(exit_code(first.pid), 0) << test::read_file(first.output);
  EXPECT_TRUE(fs::exists(log_path + ".torn-1"));
  EXPECT_EQ(test::trial_summary(log_path), test::trial_summary(whole_log));
  const SessionRecord record = read_session_record(read_event_log(log_path));
  EXPECT_EQ(record.integrity.status, LogStatus::sealed);
}

TEST(SessionRace, AParticipantFolderThatIsASymbolicLinkIsRefused) {
  const fs::path root = test::fresh_folder("race-symlink");
  const fs::path outside = root / "outside";
  fs::create_directories(outside);
  fs::create_directories(root / "results" / "tiny_pair");
  fs::create_directory_symlink(outside, root / "results" / "tiny_pair" / "R1");
  const Child run = start_run(root / "results", "", "symlink");
  EXPECT_EQ(exit_code(run.pid), 2) << test::read_file(run.output);
  EXPECT_NE(test::read_file(run.output).find("symbolic link"), std::string::npos) << test::read_file(run.output);
  EXPECT_TRUE(fs::is_empty(outside));
}

TEST(SessionRace, AStartThatFailsAfterTakingTheLockLeavesNoFolder) {
  const fs::path results = test::fresh_folder("race-failed-start");
  const StudyConfig config = parse_study_config_file(test::study_fixture("pair").string(), renderer_scene_catalog());
  SessionOptions options = test::simulated(results, "F1");
  options.gaze = "trace:" + (results / "no-such-trace.csv").string();  // read after the lock is taken
  EXPECT_THROW(run_session(config, options), InputError);
  EXPECT_TRUE(fs::is_empty(results)) << "a failed start left " << fs::directory_iterator(results)->path();
}

}  // namespace
}  // namespace fovlab

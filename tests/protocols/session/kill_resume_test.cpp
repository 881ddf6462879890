// The crash-safety promise, with real crashes: `fovlab run` is killed with SIGKILL at many random
// moments and started again each time until the session finishes; the final log must hold exactly
// the trials and answers of an uninterrupted run, end sealed, and replay must verify it. Every
// protocol: the pair study with 20 kills, the others with 8 each (CI time).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <set>
#include <thread>

#include "core/prng.h"
#include "study/log/log_integrity.h"
#include "protocols/session/replay.h"
#include "protocols/session/session.h"
#include "tests/protocols/session/session_test_support.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;

struct KillCase {
  const char* fixture;  // tests/fixtures/studies/<fixture>.toml
  const char* study;    // its name
  int kill_attempts;
};

// How CTest lists a case: the fixture and its kills, not the struct's bytes.
void PrintTo(const KillCase& study, std::ostream* out) {
  *out << study.fixture << ", " << study.kill_attempts << " kills";
}

pid_t start_run(const fs::path& results, const KillCase& study) {
  const std::string config = test::study_fixture(study.fixture).string();
  const std::string results_text = results.string();
  const pid_t pid = fork();
  if (pid == 0) {
    // The test reads the log; stderr is kept (appended) for a failure's message.
    freopen("/dev/null", "w", stdout);
    freopen((results.parent_path() / "child-stderr.txt").c_str(), "a", stderr);
    execl(FOVLAB_BINARY, FOVLAB_BINARY, "run", config.c_str(), "--participant", "K1", "--observer", "simulated",
          "--headless", "--results", results_text.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

// Waits until the child exits (returns its wait status), or until limit_s passes or the log grows
// past log_bytes (returns -1, the child still running).
int wait_for(pid_t pid, double limit_s, const std::string& log_path = "", uintmax_t log_bytes = 0) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(limit_s);
  for (;;) {
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return status;
    if (std::chrono::steady_clock::now() >= deadline) return -1;
    std::error_code error;
    if (log_bytes > 0 && fs::file_size(log_path, error) >= log_bytes && !error) return -1;
    std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
}

class SessionKill : public ::testing::TestWithParam<KillCase> {};

TEST_P(SessionKill, SigkillAtRandomMomentsThenResumeGivesTheUninterruptedTrials) {
  const KillCase study = GetParam();
  const fs::path root = test::fresh_folder(std::string("kill-") + study.fixture);
  // The uninterrupted run, timed to its first logged event (start-up and stimulus preparation
  // come before it): time-based kills are spread over that part, size-based ones over the log.
  const fs::path whole_folder = root / "whole";
  const std::string first_log = session_log_path(whole_folder.string(), study.study, "K1");
  const auto start = std::chrono::steady_clock::now();
  const pid_t whole_pid = start_run(whole_folder, study);
  ASSERT_EQ(wait_for(whole_pid, 300.0, first_log, 1), -1) << "the run ended before writing its log";
  const double startup_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const int status = wait_for(whole_pid, 300.0);
  ASSERT_TRUE(status >= 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0);
  const std::string whole_log = session_log_path((root / "whole").string(), study.study, "K1");
  const std::vector<std::string> expected = test::trial_summary(whole_log);
  ASSERT_FALSE(expected.empty());

  const fs::path results = root / "killed";
  const std::string log_path = session_log_path(results.string(), study.study, "K1");
  Pcg32 random(20261123);
  std::set<size_t> log_sizes_at_kill;  // distinct points in the session where a kill landed
  int kills = 0;
  const uintmax_t whole_bytes = fs::file_size(whole_log);
  // Attempts that are killed unless the session ends first, then one left to finish.
  const int kill_attempts = study.kill_attempts;
  for (int attempt = 0; attempt <= kill_attempts; ++attempt) {
    const pid_t pid = start_run(results, study);
    if (attempt == kill_attempts) {
      const int last = wait_for(pid, 300.0);
      ASSERT_TRUE(last >= 0 && WIFEXITED(last) && WEXITSTATUS(last) == 0) << test::read_file(root / "child-stderr.txt");
      break;
    }
    // Even attempts: a random moment of start-up and preparation (before the first
    // event); odd ones: when the log has grown by a random amount, so kills also land all over the
    // trial loop, which is short next to start-up.
    const bool by_size = attempt % 2 == 1;
    // Up to half the measured start-up: on a loaded machine a later start-up can be much quicker
    // than the measured one, and a kill planned near its end would often find the session over.
    const double delay_s = by_size ? 300.0 : random.uniform(0.0, 0.5 * startup_s);
    std::error_code no_log;
    const uintmax_t now_bytes = fs::exists(log_path) ? fs::file_size(log_path, no_log) : 0;
    const uintmax_t bytes =
        by_size ? now_bytes + 1 + static_cast<uintmax_t>(random.uniform() * double(whole_bytes) / 32) : 0;
    const int finished = wait_for(pid, delay_s, log_path, bytes);
    if (finished >= 0) {
      ASSERT_TRUE(WIFEXITED(finished) && WEXITSTATUS(finished) == 0)
          << "run failed on attempt " << attempt << ": " << test::read_file(root / "child-stderr.txt");
      break;
    }
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
    ++kills;
    if (!fs::exists(log_path)) continue;
    log_sizes_at_kill.insert(fs::file_size(log_path));
    // Killed after its last event but before it exited: the session is over (running it again
    // would rightly refuse a finished participant).
    const EventLogFile log = read_event_log(log_path);
    if (!log.events.empty() && read_session_record(log).ended) break;
  }
  ASSERT_TRUE(fs::exists(log_path));
  // Killed between session_end and its seal: running it again adds the seal and nothing else.
  if (read_session_record(read_event_log(log_path)).integrity.status != LogStatus::sealed) {
    const int last = wait_for(start_run(results, study), 300.0);
    ASSERT_TRUE(last >= 0 && WIFEXITED(last) && WEXITSTATUS(last) == 0) << test::read_file(root / "child-stderr.txt");
  }
  const SessionRecord record = read_session_record(read_event_log(log_path));
  EXPECT_EQ(record.integrity.status, LogStatus::sealed) << record.integrity.describe();
  ASSERT_TRUE(record.ended) << "the session did not finish within the attempts";
  EXPECT_GE(kills, kill_attempts * 3 / 4);
  std::printf("%d kills, at %zu distinct log sizes\n", kills, log_sizes_at_kill.size());
  EXPECT_GE(log_sizes_at_kill.size(), static_cast<size_t>(kill_attempts * 2 / 5))
      << "kills should land at several points of the session";
  EXPECT_EQ(test::trial_summary(log_path), expected);

  ReplayOptions replay;
  replay.log_path = log_path;
  replay.validation = true;
  EXPECT_EQ(replay_session(replay).difference_count, 0);
}

INSTANTIATE_TEST_SUITE_P(EveryProtocol, SessionKill,
                         ::testing::Values(KillCase{"pair", "tiny_pair", 20}, KillCase{"tiny_2afc", "tiny_2afc", 8},
                                           KillCase{"ramp", "tiny_ramp", 8}, KillCase{"slider", "tiny_slider", 8},
                                           KillCase{"rating", "tiny_rating", 8}),
                         [](const ::testing::TestParamInfo<KillCase>& param_info) {
                           return std::string(param_info.param.fixture);
                         });

}  // namespace
}  // namespace fovlab

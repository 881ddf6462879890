// Issue 14: a full disk. A session whose results folder fills up stops with one line naming the
// file, the operation and the system's reason, exit 2, leaving only complete lines (and no empty
// or partial torn-N file); once there is space, the same command resumes and loses nothing. The
// disk is a small tmpfs mounted by the test (root only: skipped with the reason elsewhere).
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>

#include "study/log/log_integrity.h"
#include "protocols/session/session.h"
#include "tests/protocols/session/session_test_support.h"
#include "tests/support/small_disk.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;
using testing::SmallDisk;

// `fovlab run` of the pair fixture for participant D1; returns the exit code, output in `output`.
int run_pair(const fs::path& results, const fs::path& output) {
  const std::string config = test::study_fixture("pair").string();
  const pid_t pid = fork();
  if (pid == 0) {
    freopen(output.c_str(), "w", stdout);
    freopen(output.c_str(), "a", stderr);
    execl(FOVLAB_BINARY, FOVLAB_BINARY, "run", config.c_str(), "--participant", "D1", "--observer", "simulated",
          "--headless", "--results", results.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

bool only_complete_lines(const std::string& text) { return text.empty() || text.back() == '\n'; }

TEST(DiskFull, ASessionStopsCleanlyWithTheReasonAndResumesOnceThereIsSpace) {
  const fs::path root = test::fresh_folder("disk-full");
  // The whole session's log, on an ordinary disk, for its size and its trials.
  ASSERT_EQ(run_pair(root / "whole", root / "whole.txt"), 0) << test::read_file(root / "whole.txt");
  const std::string whole_log = session_log_path((root / "whole").string(), "tiny_pair", "D1");
  const uintmax_t whole_bytes = fs::file_size(whole_log);

  SmallDisk disk(root / "disk");
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here (" << disk.reason() << "); needs root";
  const uintmax_t page = 4096;
  ASSERT_TRUE(disk.resize((whole_bytes / 2 / page + 1) * page));
  const fs::path results = root / "disk" / "results";
  const std::string log_path = session_log_path(results.string(), "tiny_pair", "D1");

  // 1. The disk fills mid-session.
  EXPECT_EQ(run_pair(results, root / "full.txt"), 2);
  const std::string message = test::read_file(root / "full.txt");
  EXPECT_NE(message.find("events.jsonl: writing the session log failed (No space left on device)"), std::string::npos)
      << message;
  EXPECT_TRUE(only_complete_lines(test::read_file(log_path)));
  const uintmax_t stopped_at = fs::file_size(log_path);
  EXPECT_GT(stopped_at, 0u);

  // 2. A torn last line, then a disk with no room for setting it aside: refused, nothing left.
  ASSERT_TRUE(disk.resize((whole_bytes / 2 / page + 3) * page));
  std::ofstream(log_path, std::ios::binary | std::ios::app) << "{\"event\":\"stim";
  disk.fill(root / "disk" / "filler");
  const std::string torn_log = test::read_file(log_path);
  EXPECT_EQ(run_pair(results, root / "torn.txt"), 2);
  const std::string torn_message = test::read_file(root / "torn.txt");
  EXPECT_NE(torn_message.find("No space left on device"), std::string::npos) << torn_message;
  EXPECT_FALSE(fs::exists(log_path + ".torn-1")) << "an empty or partial torn-N was left behind";
  EXPECT_EQ(test::read_file(log_path), torn_log);

  // 3. Space again: the same command resumes, with every trial of the uninterrupted session.
  fs::remove(root / "disk" / "filler");
  ASSERT_TRUE(disk.resize(8 * (whole_bytes / page + 1) * page));
  EXPECT_EQ(run_pair(results, root / "resumed.txt"), 0) << test::read_file(root / "resumed.txt");
  EXPECT_EQ(test::read_file(log_path + ".torn-1"), "{\"event\":\"stim");
  EXPECT_EQ(test::trial_summary(log_path), test::trial_summary(whole_log));
  EXPECT_EQ(read_session_record(read_event_log(log_path)).integrity.status, LogStatus::sealed);
}

}  // namespace
}  // namespace fovlab

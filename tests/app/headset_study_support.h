#pragma once
// Shared by the headset study tests at the command line (openxr_study_cli_test.cpp,
// openxr_session_life_test.cpp, ...): a small FIPR study in the headset, a fixture that runs `fovlab
// run` on it in a child process with the test runtime (tests/xr_runtime) and the OpenXR core
// validation layer on, and a follower of the log that child writes.
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/app/cli_test_support.h"
#include "tests/display/openxr/openxr_test_support.h"
#include "tests/support/fovlab_child.h"

namespace fovlab::test {

// A FIPR study (gaze-contingent) at 64x72 an eye; `more` is appended ([gaze], ...).
inline std::string headset_study(const std::string& eye_size = "eye_width_px = 64\neye_height_px = 72",
                                 const std::string& more = "") {
  return R"([study]
name = "headset_cli"
seed = 5

[display]
kind = "openxr"
)" + eye_size +
         R"(
refresh_hz = 90
left_eye_fov_deg = [-54, 49, 54, -56]
right_eye_fov_deg = [-49, 54, 54, -56]

[stimulus]
duration_s = 0.1
frames_per_second = 30

[stimulus.reference]
method = "gt"

[stimulus.test]
method = "fipr"

[levels]
parameter = "fovea_radius_deg"
values = [5, 10]

[protocol]
kind = "2afc"
question = "same"

[[block]]
scene = "primitives"
)" + more;
}

// headset_study's eyes with the gaze resting on the plane 1.5 m in front of the head.
inline const std::string kEyesAtDistance =
    "eye_width_px = 64\neye_height_px = 72\ngaze_fixation = \"fixation-distance\"\nfixation_distance_mm = 1500";

// The session's log as it is written: the events of the whole lines added since the last call.
class LogFollower {
 public:
  explicit LogFollower(std::filesystem::path path) : path_(std::move(path)) {}
  std::vector<nlohmann::json> new_events() {
    std::vector<nlohmann::json> events;
    std::ifstream file(path_, std::ios::binary);
    if (!file) return events;
    file.seekg(read_);
    std::string line;
    while (std::getline(file, line) && !file.eof()) {  // eof: a line still being written
      read_ += static_cast<std::streamoff>(line.size()) + 1;
      events.push_back(nlohmann::json::parse(line));
    }
    return events;
  }

 private:
  std::filesystem::path path_;
  std::streamoff read_ = 0;
};

// Plays the participant of the session in child `pid` while it runs: after each event of its log,
// `answer_after(event)` names the answer the session now waits for ("" for none) and `give` gives
// it; an answer the session has not taken with an event within 500 ms is given again (one given
// while a screen still counts down, a break, is dropped when the question appears). Returns the
// child's exit code, or -1 when it did not end by `limit` (it is then killed).
template <typename AnswerAfter, typename Give>
int answer_while_it_runs(pid_t pid, LogFollower& log, std::chrono::seconds limit, AnswerAfter answer_after, Give give) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point deadline = Clock::now() + limit;
  Clock::time_point given_at;
  std::string waited_for;
  for (;;) {
    // Every wait ends in an event (the answer, the instructions, the break), so any event ends the
    // wait before it.
    for (const nlohmann::json& event : log.new_events()) {
      waited_for = answer_after(event);
      if (!waited_for.empty()) {
        give(waited_for);
        given_at = Clock::now();
      }
    }
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (Clock::now() > deadline) {
      kill(pid, SIGKILL);
      exit_code(pid);
      return -1;
    }
    if (!waited_for.empty() && Clock::now() - given_at > std::chrono::milliseconds(500)) {
      give(waited_for);
      given_at = Clock::now();
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

class HeadsetStudy : public OpenXrTest {
 protected:
  std::filesystem::path write(const std::string& name, const std::string& text) {
    return cli_test::write_file(scratch_.path() / name, text);
  }
  // fovlab run in the scratch folder with the test runtime (`switches`: its environment switches).
  cli_test::CommandResult run_study(const std::filesystem::path& config, const std::string& switches = "",
                                    const std::string& runtime_json = FOVLAB_TEST_XR_RUNTIME_JSON,
                                    const std::string& flags = "") {
    return cli_test::run("run " + config.string() + " --participant P01 --results " + results_.string() + flags,
                         child_environment(runtime_json) + " " + switches);
  }
  std::filesystem::path results_ = scratch_.path() / "results";
};

}  // namespace fovlab::test

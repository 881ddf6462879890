#pragma once
// The fovlab binary run as a child process that a test can stop at a pause point
// (core/test_pause.h: FOVLAB_TEST_PAUSE_AT) and act on while it waits: two processes lined up at
// exact phases, or a file changed at an exact moment of a session.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

namespace fovlab::test {

// `fovlab ARGS...` started with FOVLAB_TEST_PAUSE_AT = `pause_at` (unset when empty); its stdout and
// stderr both go to `output`. Returns the child's pid.
inline pid_t start_fovlab(const std::vector<std::string>& args, const std::string& pause_at,
                          const std::filesystem::path& output) {
  const pid_t pid = fork();
  if (pid == 0) {
    if (pause_at.empty()) ::unsetenv("FOVLAB_TEST_PAUSE_AT");
    else ::setenv("FOVLAB_TEST_PAUSE_AT", pause_at.c_str(), 1);
    // Both appended (a stdout opened with "w" writes at its own offset, over stderr's lines).
    std::fclose(std::fopen(output.c_str(), "w"));
    if (!std::freopen(output.c_str(), "a", stdout) || !std::freopen(output.c_str(), "a", stderr)) _exit(126);
    std::vector<char*> argv{const_cast<char*>(FOVLAB_BINARY)};
    for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
    argv.push_back(nullptr);
    execv(FOVLAB_BINARY, argv.data());
    _exit(127);
  }
  return pid;
}

// Waits until the child has stopped itself at its pause point; false when it exited instead or the
// limit passed.
inline bool wait_until_stopped(pid_t pid, double limit_s = 300.0) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(limit_s);
  while (std::chrono::steady_clock::now() < deadline) {
    int status = 0;
    const pid_t got = waitpid(pid, &status, WNOHANG | WUNTRACED);
    if (got == pid) return WIFSTOPPED(status);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

// The child's exit code once it ends; -1 when a signal ended it.
inline int exit_code(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace fovlab::test

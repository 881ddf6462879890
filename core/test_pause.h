#pragma once
// Test-only pause points. When the environment variable FOVLAB_TEST_PAUSE_AT names a point the
// process reaches, it stops itself there (SIGSTOP) until a test sends SIGCONT: a test can line two
// processes up at exact phases (tests/protocols/session/session_race_test.cpp). Unset, it costs one
// getenv at each of a handful of points per session.
#include <signal.h>

#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>

namespace fovlab {

inline void test_pause_point(std::string_view point) {
  const char* pause_at = std::getenv("FOVLAB_TEST_PAUSE_AT");
  if (pause_at && point == pause_at) ::raise(SIGSTOP);
}

// The same at a counted point: FOVLAB_TEST_PAUSE_AT=trial_end:3 stops a run once its third trial is
// on disk (a session that stays live, its log open, while a test acts on its folder).
inline void test_pause_point(std::string_view point, long count) {
  const char* pause_at = std::getenv("FOVLAB_TEST_PAUSE_AT");
  if (!pause_at) return;
  const std::string_view wanted(pause_at);
  if (wanted.size() > point.size() && wanted.starts_with(point) && wanted[point.size()] == ':' &&
      wanted.substr(point.size() + 1) == std::to_string(count))
    ::raise(SIGSTOP);
}

// Test-only: FOVLAB_TEST_CLOSE_AT_S=T makes a headless presenter report its window closed once its
// virtual clock reaches T seconds, so a test can stop a session at an exact moment of its timeline
// (the session sees it at its next wait for an answer or a key). Unset or not a number: never.
inline std::optional<double> test_close_at_s() {
  const char* text = std::getenv("FOVLAB_TEST_CLOSE_AT_S");
  if (!text || !*text) return std::nullopt;
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  return *end == '\0' ? std::optional<double>(value) : std::nullopt;
}

}  // namespace fovlab

#pragma once
// Test-only pause points. When the environment variable FOVLAB_TEST_PAUSE_AT names a point the
// process reaches, it stops itself there (SIGSTOP) until a test sends SIGCONT: a test can line two
// processes up at exact phases (tests/protocols/session/session_race_test.cpp). Unset, it costs one
// getenv at each of a handful of points per session.
#include <signal.h>

#include <cstdlib>
#include <string_view>

namespace fovlab {

inline void test_pause_point(std::string_view point) {
  const char* pause_at = std::getenv("FOVLAB_TEST_PAUSE_AT");
  if (pause_at && point == pause_at) ::raise(SIGSTOP);
}

}  // namespace fovlab

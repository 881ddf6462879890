#pragma once
// Test hooks, present only in a build with the tests (FOVLAB_BUILD_TESTS, the Debug build of the
// README's test command: core/test_pause.cpp is then compiled with FOVLAB_TEST_HOOKS). In the product
// build (Release, the README's main command) every function here does nothing and no environment
// variable is read.
//
// Pause points: when FOVLAB_TEST_PAUSE_AT names a point the process reaches, it stops itself there
// (SIGSTOP) until a test sends SIGCONT, so a test can line two processes up at exact phases
// (tests/protocols/session/session_race_test.cpp drives the real fovlab binary this way).
#include <optional>
#include <string_view>

namespace fovlab {

void test_pause_point(std::string_view point);

// The same at a counted point: FOVLAB_TEST_PAUSE_AT=trial_end:3 stops a run once its third trial is
// on disk (a session that stays live, its log open, while a test acts on its folder).
void test_pause_point(std::string_view point, long count);

// FOVLAB_TEST_CLOSE_AT_S=T makes a headless presenter report its window closed once its virtual
// clock reaches T seconds, so a test can stop a session at an exact moment of its timeline (the
// session sees it at its next wait for an answer or a key). Unset, not a number, or no hooks: never.
std::optional<double> test_close_at_s();

}  // namespace fovlab

#include "core/test_pause.h"

#if FOVLAB_TEST_HOOKS
#include <signal.h>

#include <cstdlib>
#include <string>
#endif

namespace fovlab {

#if FOVLAB_TEST_HOOKS

void test_pause_point(std::string_view point) {
  const char* pause_at = std::getenv("FOVLAB_TEST_PAUSE_AT");
  if (pause_at && point == pause_at) ::raise(SIGSTOP);
}

void test_pause_point(std::string_view point, long count) {
  const char* pause_at = std::getenv("FOVLAB_TEST_PAUSE_AT");
  if (!pause_at) return;
  const std::string_view wanted(pause_at);
  if (wanted.size() > point.size() && wanted.starts_with(point) && wanted[point.size()] == ':' &&
      wanted.substr(point.size() + 1) == std::to_string(count))
    ::raise(SIGSTOP);
}

std::optional<double> test_close_at_s() {
  const char* text = std::getenv("FOVLAB_TEST_CLOSE_AT_S");
  if (!text || !*text) return std::nullopt;
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  return *end == '\0' ? std::optional<double>(value) : std::nullopt;
}

#else

void test_pause_point(std::string_view) {}
void test_pause_point(std::string_view, long) {}
std::optional<double> test_close_at_s() { return std::nullopt; }

#endif

}  // namespace fovlab

// libFuzzer harness: the gaze-trace parser (protocols/gaze/trace_gaze_source.h, parse_gaze_trace).
// Contract: parse_gaze_trace throws fovlab::InputError for bad input, with a message of one line
// that starts with the name; any other exception, a crash, a sanitizer report or a hang is a bug.
// What it returns must be a trace TraceGazeSource can replay (invariants below). Built two ways
// (tests/fuzz/fuzz.cmake): fovlab_gaze_trace_fuzz (clang, libFuzzer + ASan + UBSan; scripts/fuzz)
// and fovlab_gaze_trace_corpus (corpus_runner.cpp replays tests/fuzz/corpus/gaze_trace under CTest).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "core/input_error.h"
#include "protocols/gaze/trace_gaze_source.h"

namespace {

void expect(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "gaze_trace_fuzz: violates: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::vector<fovlab::GazeSample> samples;
  try {
    samples = fovlab::parse_gaze_trace(text, "fuzz.csv");
  } catch (const fovlab::InputError& error) {
    const std::string message = error.what();
    expect(message.rfind("fuzz.csv:", 0) == 0, "an error starts with the name");
    expect(message.find('\n') == std::string::npos && message.find('\r') == std::string::npos, "an error is one line");
    return 0;
  }
  expect(!samples.empty(), "at least one sample");
  for (size_t i = 0; i < samples.size(); ++i) {
    const fovlab::GazeSample& sample = samples[i];
    expect(std::isfinite(sample.time_s), "finite times");
    expect(i == 0 || samples[i - 1].time_s <= sample.time_s, "non-decreasing times");
    expect(std::isfinite(sample.x_px) && std::isfinite(sample.y_px), "finite positions (0 when there is none)");
    expect(sample.valid == sample.invalid_reason.empty(), "a reason exactly for the invalid samples");
    if (sample.invalid_reason == "no_data" || sample.invalid_reason == "not_finite")
      expect(sample.x_px == 0.0 && sample.y_px == 0.0, "no position: x_px = y_px = 0");
  }
  return 0;
}

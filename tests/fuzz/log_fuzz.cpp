// libFuzzer harness: the session-log reader (protocols/log/event_log.h, session_record.h).
// Contract: parse_event_log and read_session_record throw fovlab::InputError for bad input; any
// other exception, a crash, a sanitizer report or a hang is a bug. Parses the bytes as an
// events.jsonl, then, when that succeeded, builds the session record from it. Built two ways
// (tests/fuzz/fuzz.cmake): fovlab_log_fuzz (clang, libFuzzer + ASan + UBSan; scripts/fuzz) and
// fovlab_log_corpus (corpus_runner.cpp replays tests/fuzz/corpus/log under CTest).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/input_error.h"
#include "protocols/log/event_log.h"
#include "protocols/log/session_record.h"

namespace {

void expect(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "log_fuzz: violates: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    const fovlab::EventLogFile log = fovlab::parse_event_log(bytes, "fuzz.jsonl");
    expect(log.events.size() == log.line_numbers.size(), "one line number per event");
    expect(log.intact_bytes <= bytes.size(), "intact_bytes within the input");
    expect(log.torn_tail.has_value() == (log.intact_bytes < bytes.size()), "torn_tail is the rest");
    const fovlab::SessionRecord record = fovlab::read_session_record(log);
    expect(record.trials.size() <= log.events.size(), "no more trials than events");
    for (size_t i = 1; i < record.trials.size(); ++i)
      expect(record.trials[i - 1].index < record.trials[i].index, "trials ordered by index, one per index");
  } catch (const fovlab::InputError&) {
    // Rejected input, as the contract says.
  }
  return 0;
}

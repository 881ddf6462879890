// libFuzzer harness: the session-log readers (study/log/event_log.h, session_record.h, and the
// fast scan session_scan.h that fovlab analyze uses).
// Contract: parse_event_log, read_session_record and scan_session_bytes throw fovlab::InputError
// for bad input; any other exception, a crash, a sanitizer report or a hang is a bug. Parses the
// bytes as an events.jsonl, then, when that succeeded, builds the session record from it. Both
// readers stand on one line reader (study/log/log_lines.h: the JSON grammar of every value, the
// nesting cap, one object a line, seq and chain), so they must tell the same story of any bytes:
// both refuse them, or both accept them with the same trials, the same session state, the same
// chain break and the same verdict (sealed, unsealed or broken, at the same line). Built two ways
// (tests/fuzz/fuzz.cmake): fovlab_log_fuzz (clang, libFuzzer + ASan + UBSan; scripts/fuzz) and
// fovlab_log_corpus (corpus_runner.cpp replays tests/fuzz/corpus/log under CTest).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "core/input_error.h"
#include "study/log/event_log.h"
#include "study/log/session_record.h"
#include "study/log/session_scan.h"

namespace {

void expect(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "log_fuzz: violates: %s\n", what);
  std::abort();
}

// The fast scan, or nullopt when it rejects the bytes.
std::optional<fovlab::ScannedSession> scan(const std::string& bytes) {
  try {
    return fovlab::scan_session_bytes(bytes, "fuzz.jsonl");
  } catch (const fovlab::InputError&) {
    return std::nullopt;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const std::optional<fovlab::ScannedSession> scanned = scan(bytes);
  std::optional<fovlab::SessionRecord> full;
  std::optional<fovlab::EventLogFile> full_log;
  try {
    const fovlab::EventLogFile log = fovlab::parse_event_log(bytes, "fuzz.jsonl");
    expect(log.events.size() == log.line_numbers.size(), "one line number per event");
    expect(log.intact_bytes <= bytes.size(), "intact_bytes within the input");
    expect(log.torn_tail.has_value() == (log.intact_bytes < bytes.size()), "torn_tail is the rest");
    const fovlab::SessionRecord record = fovlab::read_session_record(log);
    expect(record.trials.size() <= log.events.size(), "no more trials than events");
    for (size_t i = 1; i < record.trials.size(); ++i)
      expect(record.trials[i - 1].index < record.trials[i].index, "trials ordered by index, one per index");
    full = record;
    full_log = log;
  } catch (const fovlab::InputError&) {
    // Rejected input, as the contract says.
  }
  expect(scanned.has_value() == full.has_value(), "both readers refuse the same bytes");
  if (full) {
    expect(scanned->first_chain_error_line == full_log->first_chain_error_line, "the same chain break");
    expect(scanned->header_chain == full_log->header_chain, "the same session identity");
    expect(scanned->trials.size() == full->trials.size(), "the scan finds the same trials");
    for (size_t i = 0; i < full->trials.size(); ++i)
      expect(scanned->trials[i].index == full->trials[i].index &&
                 scanned->trials[i].answers.size() == full->trials[i].responses.size(),
             "the same trial indices and answers");
    expect(scanned->excluded == full->excluded && scanned->ended == full->ended &&
               scanned->incomplete_trial == full->incomplete_trial,
           "the same session state");
    expect(scanned->integrity.status == full->integrity.status && scanned->integrity.line == full->integrity.line,
           "the same integrity verdict (sealed, unsealed or broken, at the same line)");
  }
  return 0;
}

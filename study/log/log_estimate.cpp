#include "study/log/log_estimate.h"

#include <algorithm>
#include <cmath>

#include "core/input_error.h"
#include "core/input_file.h"
#include "study/log/event_log.h"

namespace fovlab {
namespace {

// The widths, in bytes, each at its widest (docs/log-schema.md; measured on logs in
// tests/app/study_cli_test.cpp, StudyCli.LogsOfEveryProtocolStayWithinTheEstimate).
constexpr uint64_t kEventBytes = 260;         // {"event":...,"seq":N,"t":T,"chain":64 hex,"mac":64 hex}
constexpr uint64_t kTrialStartBytes = 300;    // besides the event, the sequence and the names
constexpr uint64_t kSequenceEntryBytes = 12;  // a stimulus id in trial_start's sequence
constexpr uint64_t kAnswerBytes = 120;        // response: trial, step, answer, key, rt_s
constexpr uint64_t kSmallEventBytes = 120;    // trial_end, attention_check, slider_saved, block_start...
constexpr uint64_t kStimulusBytes = 300;      // a stimulus event's trial, step, id, onset, clock, drops
constexpr uint64_t kRefreshBytes = 140;       // present_s, frame, hash, gaze, gaze_acquired_s, gaze_age_s, invalid_gaze
constexpr uint64_t kValidationTargetBytes = 200;
constexpr uint64_t kValidationSampleBytes = 20;  // a gaze sample [x, y]
constexpr uint64_t kHeaderBytes = 16384;         // the header's fixed fields, device, display, observer
constexpr uint64_t kHeaderStimulusBytes = 2048;  // one planned stimulus in the header's `stimuli`

uint64_t escaped_text_bytes(const std::string& text) {
  return 2 * uint64_t(text.size());
}  // JSON escapes at most double

}  // namespace

LogSizeEstimate estimate_log_size(const StudyPlan& plan) {
  const StudyConfig& config = plan.config;
  const uint64_t refreshes = uint64_t(std::max(config.stimulus.frame_count(), 1)) *
                             uint64_t(std::max(config.stimulus.refreshes_per_frame(config.display.refresh_hz), 1));
  const uint64_t presentation = kEventBytes + kStimulusBytes + refreshes * kRefreshBytes;
  const uint64_t answer = kEventBytes + kAnswerBytes;
  const uint64_t small_event = kEventBytes + kSmallEventBytes;

  LogSizeEstimate estimate;
  estimate.bytes = kEventBytes + kHeaderBytes + escaped_text_bytes(config.source_text) +
                   escaped_text_bytes(config.conditions_csv) + uint64_t(plan.stimuli.size()) * kHeaderStimulusBytes;
  for (const Trial& trial : plan.trials) {
    // An adaptive trial's intervals are chosen as it runs: two, as a comparison's.
    const uint64_t sequence = trial.track >= 0 ? 2 : uint64_t(trial.sequence.size());
    uint64_t presentations = sequence, answers = 1, extra = 0;
    switch (config.protocol.kind) {
      case ProtocolKind::ramp:
        answers = sequence > 0 ? sequence - 1 : 0;
        break;
      case ProtocolKind::slider:
        // The reference, then per action the ladder's stimulus and an answer, and the reference again
        // when asked for: two actions a ladder step, each with both.
        answers = 2 * std::max<uint64_t>(sequence, 1);
        presentations = 1 + 2 * answers;
        extra = small_event;  // slider_saved
        break;
      default:
        break;
    }
    uint64_t bytes = kEventBytes + kTrialStartBytes + 2 * (trial.condition.size() + trial.variant.size()) +
                     sequence * kSequenceEntryBytes + presentations * presentation + answers * answer + extra +
                     small_event;                         // trial_end
    if (trial.attention_check) bytes += 2 * small_event;  // attention_check, and a break
    estimate.widest_trial_bytes = std::max(estimate.widest_trial_bytes, bytes);
    estimate.bytes += bytes;
  }
  // Per block its start (and a rest); per run its instructions, end or pause, and seal; the
  // eye-tracker validations: at the start, after each rest and attention break, each attempt.
  estimate.bytes += uint64_t(plan.blocks.size()) * 2 * small_event + 8 * small_event;
  if (config.validation.enabled) {
    const uint64_t samples = uint64_t(std::floor(config.validation.target_s * config.display.refresh_hz + 1e-9));
    const uint64_t validation =
        kEventBytes + kSmallEventBytes +
        uint64_t(config.validation.targets) * (kValidationTargetBytes + samples * kValidationSampleBytes);
    const uint64_t validations =
        (uint64_t(plan.blocks.size()) + uint64_t(std::max(config.attention.max_errors, 0)) + 1) *
        uint64_t(std::max(config.validation.max_attempts, 1));
    estimate.bytes += validations * validation;
  }
  return estimate;
}

void check_log_fits_readers(const StudyPlan& plan, const std::string& source) {
  const LogSizeEstimate estimate = estimate_log_size(plan);
  if (estimate.bytes <= max_log_bytes) return;
  throw InputError(
      source + ": " + std::to_string(plan.trials.size()) + " trials: a session's log would take up to " +
      std::to_string(estimate.bytes) + " bytes (estimated from the plan, up to " +
      std::to_string(estimate.widest_trial_bytes) + " bytes a trial), more than the " + std::to_string(max_log_bytes) +
      " bytes (" + byte_size_text(max_log_bytes) +
      ") the log readers take; expected fewer trials ([protocol] repeats, the conditions), shorter stimuli "
      "([stimulus] duration_s) or a lower [display] refresh_hz");
}

}  // namespace fovlab

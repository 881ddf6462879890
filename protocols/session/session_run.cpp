#include "protocols/session/session_run.h"

#include <cctype>
#include <cmath>
#include <filesystem>

#include "display/frame_io.h"
#include "display/text_screen.h"
#include "display/window_presenter.h"
#include "study/log/log_events.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;

}  // namespace

SessionRun::SessionRun(const StudyPlan& plan, const SessionOptions& options, Presenter& presenter, GazeSource& gaze,
           ResponseSource& responses, StimulusLibrary& library, EventLogWriter& log, double time_base_s)
    : plan_(plan), options_(options), presenter_(presenter), gaze_(gaze), responses_(responses),
      library_(library), log_(log), time_base_s_(time_base_s) {}

void SessionRun::log(nlohmann::json event) {
  if (!event.contains("t")) event["t"] = t();
  const bool trial_end = event_kind(event) == TrialEndEvent::kind;
  log_.append(std::move(event));
  ++events_written_;
  if (trial_end) ++trials_completed_;
}

void SessionRun::show_text(const std::string& text, const std::string& screen_kind) {
  const bool capture = wants_screenshot(screen_kind);
  if (presenter_.is_headless() && !capture) return;  // nothing to show: the text is not even drawn
  const Rgba8Frame frame = render_text_screen(plan_.config.display.width_px, plan_.config.display.height_px, text);
  if (!presenter_.is_headless()) presenter_.present(frame);
  if (capture) save_screenshot(screen_kind, frame);
}

void SessionRun::show_fixation(double duration_s) {
  if (duration_s <= 0) return;
  const double until = presenter_.now_s() + duration_s;
  const bool capture = wants_screenshot("fixation");
  if (!presenter_.is_headless() || capture) {
    const Rgba8Frame cross = fixation_cross_frame(plan_.config.display.width_px, plan_.config.display.height_px);
    if (!presenter_.is_headless()) presenter_.present(cross);
    if (capture) save_screenshot("fixation", cross);
  }
  presenter_.wait_until(until);
}

void SessionRun::wait_for_key() {
  AnswerRequest request{nullptr, 0, 0, presenter_.now_s()};
  responses_.await(request, presenter_, 0.0);
}

void SessionRun::take_break(const std::string& text, double duration_s, const std::string& screen_kind) {
  const double end = presenter_.now_s() + duration_s;
  for (int left = static_cast<int>(std::ceil(duration_s - 1e-9)); left > 0; --left) {
    show_text(text + "\n\n" + std::to_string(left) + " s", screen_kind);
    presenter_.wait_until(end - (left - 1));
  }
  show_text(text + "\n\nPress an answer key to continue.", screen_kind + "_end");
  wait_for_key();
}

void SessionRun::show_black(double duration_s) {
  if (duration_s <= 0) return;
  const double until = presenter_.now_s() + duration_s;
  if (!presenter_.is_headless()) presenter_.present(black_frame(plan_.config.display.width_px, plan_.config.display.height_px));
  presenter_.wait_until(until);
}

bool SessionRun::wants_screenshot(const std::string& kind) const {
  return !options_.screenshots_dir.empty() && !screenshots_taken_.count(kind);
}

void SessionRun::save_screenshot(const std::string& kind, const Rgba8Frame& frame) {
  if (!wants_screenshot(kind)) return;
  screenshots_taken_.insert(kind);
  fs::create_directories(options_.screenshots_dir);
  // A window saves what its swapchain held (letterbox included); headless, the frame itself.
  const auto* window = dynamic_cast<WindowPresenter*>(&presenter_);
  write_frame_image(fs::path(options_.screenshots_dir) / (kind + ".png"), window ? window->screenshot() : frame);
}

void SessionRun::present_stimulus(const Trial& trial, int step, int stimulus_id) {
  const PlannedStimulus& stimulus = plan_.stimuli.at(static_cast<size_t>(stimulus_id));
  const int refreshes = plan_.config.stimulus.refreshes_per_frame(plan_.config.display.refresh_hz);
  StimulusEvent event;
  event.trial = trial.index;
  event.step = step;
  event.stimulus = stimulus_id;
  event.onset_s = t();
  std::vector<std::optional<double>> acquired, ages;
  int dropped = 0;
  double previous = -1.0;
  for (int frame = 0; frame < stimulus.spec.frame_count; ++frame) {
    for (int refresh = 0; refresh < refreshes; ++refresh) {
      // Rounded to kGazeStepPx by sanitize_gaze: what is logged is exactly what is used.
      const GazeSample sample = sanitize_gaze(gaze_.sample(t()), stimulus.spec.width_px, stimulus.spec.height_px,
                                              last_valid_gaze_ ? &*last_valid_gaze_ : nullptr);
      if (sample.valid) last_valid_gaze_ = sample;
      // Image `frame * refreshes + refresh` of this presentation, its position in the logged arrays:
      // a gaze-dependent stimulus (fipr) renders it now with this refresh's gaze (replay does the same).
      const StimulusImage image{frame, frame * refreshes + refresh, sample};
      const PreparedFrame& shown = library_.frame(stimulus_id, stimulus.spec, image);
      const double shown_at =
          time_base_s_ + (shown.on_device ? presenter_.present(shown.on_device) : presenter_.present(shown.image));
      if (previous >= 0) {
        const long periods = std::lround((shown_at - previous) * presenter_.refresh_hz());
        if (periods > 1) dropped += static_cast<int>(periods - 1);
      }
      previous = shown_at;
      if (!sample.valid)
        event.invalid_gaze.push_back({static_cast<int>(event.present_s.size()), sample.invalid_reason});
      event.present_s.push_back(shown_at);
      event.frame.push_back(frame);
      event.hash.push_back(library_.hash(shown));  // a live frame's: read back now, after its present
      if (frame == 0 && refresh == refreshes - 1 && wants_screenshot("stimulus")) save_screenshot("stimulus", shown.image);
      event.gaze.push_back({sample.x_px, sample.y_px});
      // The sample's own time (already on the session clock: the source was asked at t()) and its
      // age when the frame made with it was presented (null: the tracker had no sample).
      if (sample.acquired_s) {
        const double acquired_s = *sample.acquired_s;
        acquired.push_back(acquired_s);
        ages.push_back(shown_at - acquired_s);
        gaze_age_s_.push_back(shown_at - acquired_s);
      } else {
        acquired.push_back(std::nullopt);
        ages.push_back(std::nullopt);
      }
    }
  }
  event.stamp.t = t();
  event.dropped_frames = dropped;
  event.gaze_acquired_s = std::move(acquired);
  event.gaze_age_s = std::move(ages);
  event.present_clock = presenter_.present_clock();
  log(to_json(event));
  dropped_frames_ += dropped;
}

std::string question_screen_text(const QuestionConfig& question) {
  std::string keys;
  for (const auto& [answer, answer_keys] : question.answers) {
    std::string key = answer_keys.front();
    if (key.size() == 1) key[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(key[0])));
    keys += (keys.empty() ? "" : "\n") + key + ": " + answer;
  }
  return question.text + "\n\n" + keys;
}

Answer SessionRun::ask(const Trial& trial, int step, int ladder_index) {
  show_text(question_screen_text(plan_.config.protocol.question), "question");
  AnswerRequest request{&trial, step, ladder_index, presenter_.now_s()};
  const std::optional<Answer> answer =
      responses_.await(request, presenter_, plan_.config.timing.response_timeout_s);
  Answer result = answer.value_or(Answer{"", "", presenter_.now_s()});
  ResponseEvent event;
  event.stamp.t = time_base_s_ + result.time_s;
  event.trial = trial.index;
  event.step = step;
  event.answer = result.answer;
  event.key = result.key;
  event.rt_s = result.time_s - request.onset_s;
  log(to_json(event));
  return result;
}

std::string SessionRun::run_comparison(const Trial& trial) {
  for (size_t step = 0; step < trial.sequence.size(); ++step) {
    if (step > 0) show_black(plan_.config.timing.black_interval_s);
    present_stimulus(trial, static_cast<int>(step), trial.sequence[step]);
  }
  return ask(trial, 0, 0).answer;
}

void SessionRun::run_ramp(const Trial& trial) {
  for (size_t step = 0; step < trial.sequence.size(); ++step) {
    if (step > 0) show_black(plan_.config.timing.black_interval_s);
    present_stimulus(trial, static_cast<int>(step), trial.sequence[step]);
    if (step > 0) ask(trial, static_cast<int>(step), 0);
  }
}

void SessionRun::run_slider(const Trial& trial) {
  present_stimulus(trial, 0, trial.reference);
  int ladder_index = trial.slider_start;
  int step = 1;
  for (int action = 0;; ++action) {
    show_black(plan_.config.timing.black_interval_s);
    present_stimulus(trial, step++, trial.sequence.at(static_cast<size_t>(ladder_index)));
    const Answer answer = ask(trial, action, ladder_index);
    if (answer.answer == answers::save) {
      SliderSavedEvent saved;
      saved.trial = trial.index;
      saved.ladder_index = ladder_index;
      saved.stimulus = trial.sequence.at(static_cast<size_t>(ladder_index));
      saved.level = plan_.stimuli.at(static_cast<size_t>(saved.stimulus)).level.value_or(0.0);
      log(to_json(saved));
      return;
    }
    ladder_index = next_ladder_index(trial, answer.answer, ladder_index);
    if (answer.answer == answers::reference) {
      show_black(plan_.config.timing.black_interval_s);
      present_stimulus(trial, step++, trial.reference);
    }
  }
}

bool SessionRun::run_trials(int first, int attention_errors, bool resumed) {
  const StudyConfig& config = plan_.config;
  const bool checks_on = config.attention.share > 0;
  const auto exclude = [&](bool excluded_logged, int completed_trials) {
    if (!excluded_logged) log(to_json(ExcludedEvent{{}, attention_errors, config.attention.max_errors}));
    log(to_json(SessionEndEvent{{}, SessionEndEvent::excluded, completed_trials}));
    show_text(config.attention.excluded_message, "excluded");
    try {
      wait_for_key();
    } catch (const SessionAborted&) {  // the session has ended: closing the window now only closes it
    }
    return false;
  };
  // A crash after the trial that reached max_errors (before session_end): the session is over.
  if (checks_on && attention_errors >= config.attention.max_errors) return exclude(excluded_logged_, first);
  {
    show_text(resumed ? "The session resumes where it stopped.\n\n" + config.instructions : config.instructions,
              "instructions");
    const double onset_s = presenter_.now_s();
    wait_for_key();
    log(to_json(InstructionsEvent{{}, time_base_s_ + onset_s}));
  }
  for (size_t index = static_cast<size_t>(first); index < plan_.trials.size(); ++index) {
    const Trial& trial = plan_.trials[index];
    const PlannedBlock& block = plan_.blocks.at(static_cast<size_t>(trial.block));
    if (trial.index == block.first_trial || static_cast<int>(index) == first) {
      if (trial.index == block.first_trial && trial.block > 0 && config.timing.rest_between_blocks_s > 0) {
        const double start = t();
        take_break("Rest before the next block.", config.timing.rest_between_blocks_s, "rest");
        log(to_json(BreakEvent{{}, BreakEvent::rest, std::nullopt, start, t() - start}));
      }
      log(to_json(BlockStartEvent{{}, trial.block, block.name, block.scene}));
    }
    TrialStartEvent start;
    start.trial = trial.index;
    start.block = trial.block;
    start.condition = trial.condition;
    start.variant = trial.variant;
    start.level = trial.level;
    start.attention_check = trial.attention_check;
    start.sequence = trial.sequence;
    start.reference = trial.reference;
    if (config.protocol.kind == ProtocolKind::ramp) start.ramp_toward_reference = trial.ramp_toward_reference;
    else if (config.protocol.kind == ProtocolKind::slider) start.slider_start = trial.slider_start;
    else start.reference_first = trial.reference_first;
    log(to_json(start));

    show_fixation(config.timing.fixation_s);
    std::string answer;
    if (config.protocol.kind == ProtocolKind::ramp) run_ramp(trial);
    else if (config.protocol.kind == ProtocolKind::slider) run_slider(trial);
    else answer = run_comparison(trial);

    if (trial.attention_check) {
      const bool correct = answer == identical_answer(config.protocol);
      if (!correct) ++attention_errors;
      log(to_json(AttentionCheckEvent{{}, trial.index, correct, attention_errors}));
      if (!correct && attention_errors < config.attention.max_errors && config.attention.break_s > 0) {
        const double break_start = t();
        try {
          take_break("Please take a short break.", config.attention.break_s, "break");
        } catch (const SessionAborted&) {
          // Stopped at "press to continue": the trial and its wrong answer are complete all the same,
          // so a resumed session cannot ask the check again and forget the error.
          log(to_json(BreakEvent{{}, BreakEvent::attention_check, trial.index, break_start, t() - break_start}));
          log(to_json(TrialEndEvent{{}, trial.index}));
          throw;
        }
        log(to_json(BreakEvent{{}, BreakEvent::attention_check, trial.index, break_start, t() - break_start}));
      }
    }
    log(to_json(TrialEndEvent{{}, trial.index}));
    if (options_.trial_progress) options_.trial_progress(double(index + 1) / double(plan_.trials.size()));
    if (checks_on && attention_errors >= config.attention.max_errors) return exclude(false, trial.index + 1);
    show_black(config.timing.inter_trial_s);
  }
  show_text("Thank you. The session is complete.", "end");
  log(to_json(SessionEndEvent{{}, SessionEndEvent::completed, static_cast<int>(plan_.trials.size())}));
  return true;
}

}  // namespace fovlab

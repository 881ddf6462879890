#include "protocols/session/session_run.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/number_text.h"
#include "core/prng.h"
#include "core/test_pause.h"
#include "display/frame_io.h"
#include "display/text_screen.h"
#include "display/window_presenter.h"
#include "protocols/gaze/tracker_validation.h"
#include "protocols/session/head_tracking.h"
#include "study/log/log_events.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;

// "0.420 deg" (three decimals: a tracker's precision is a few hundredths of a degree).
std::string degrees_text(const std::optional<double>& degrees) {
  if (!degrees) return "none (a target had too few valid samples)";
  char text[32];
  std::snprintf(text, sizeof text, "%.3f deg", *degrees);
  return text;
}

// The fixation target a gaze source is told about, cleared however its scope ends.
class FixationTargetScope {
 public:
  FixationTargetScope(GazeSource& gaze, double x_px, double y_px) : gaze_(gaze) {
    gaze_.set_fixation_target(std::pair{x_px, y_px});
  }
  ~FixationTargetScope() { gaze_.set_fixation_target(std::nullopt); }
  FixationTargetScope(const FixationTargetScope&) = delete;
  FixationTargetScope& operator=(const FixationTargetScope&) = delete;

 private:
  GazeSource& gaze_;
};

}  // namespace

SessionRun::SessionRun(const StudyPlan& plan, const SessionOptions& options, Presenter& presenter, GazeSource& gaze,
                       ResponseSource& responses, StimulusLibrary& library, EventLogWriter& log, double time_base_s,
                       const RightEyeStimuli* right_eye)
    : plan_(plan),
      options_(options),
      presenter_(presenter),
      gaze_(gaze),
      responses_(responses),
      library_(library),
      log_(log),
      time_base_s_(time_base_s),
      right_eye_(right_eye) {
  if ((presenter.view_count() == 2) != (right_eye != nullptr))
    throw std::logic_error("SessionRun: a headset presenter needs the right eye's stimuli, and only it");
}

void SessionRun::log(nlohmann::json event) {
  if (!event.contains("t")) event["t"] = t();
  const bool trial_end = event_kind(event) == TrialEndEvent::kind;
  log_.append(std::move(event));
  ++events_written_;
  if (!trial_end) return;
  ++trials_completed_;
  test_pause_point("trial_end", trials_completed_);
}

void SessionRun::show_screen(const std::string& screen_kind, const std::function<Rgba8Frame()>& draw) {
  const bool capture = wants_screenshot(screen_kind);
  if (presenter_.is_headless() && !capture) return;  // nothing to show: not even drawn
  const Rgba8Frame frame = draw();
  if (!presenter_.is_headless()) presenter_.present(frame);
  if (capture) save_screenshot(screen_kind, frame);
}

void SessionRun::show_text(const std::string& text, const std::string& screen_kind) {
  show_screen(screen_kind,
              [&] { return render_text_screen(plan_.config.display.width_px, plan_.config.display.height_px, text); });
}

void SessionRun::show_fixation(double duration_s) {
  if (duration_s <= 0) return;
  const double until = presenter_.now_s() + duration_s;
  show_screen("fixation",
              [&] { return fixation_cross_frame(plan_.config.display.width_px, plan_.config.display.height_px); });
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
  if (!presenter_.is_headless())
    presenter_.present(black_frame(plan_.config.display.width_px, plan_.config.display.height_px));
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
  std::vector<std::string> right_hashes;
  std::vector<std::array<double, 2>> right_gaze;
  std::vector<std::array<double, 7>> head_poses;  // head-tracked: each refresh's, as rendered
  int dropped = 0;
  std::optional<int> late;  // counted where the presenter can tell (last_frame_late)
  double previous = -1.0;
  for (int frame = 0; frame < stimulus.spec.frame_count; ++frame) {
    for (int refresh = 0; refresh < refreshes; ++refresh) {
      // Rounded to kGazeStepPx by sanitize_gaze: what is logged is exactly what is used.
      std::array<GazeSample, 2> eye_samples;
      // Head-tracked: the head at this refresh, rounded as logged (the last one held when the runtime has none).
      std::optional<HeadPose> head;
      if (right_eye_ && right_eye_->head_pose) {
        head = sanitize_head_pose(right_eye_->head_pose(), last_head_pose_ ? &*last_head_pose_ : nullptr);
        last_head_pose_ = head;
        head_poses.push_back(head_pose_entry(*head));
      }
      if (right_eye_) {
        eye_samples = headset_gaze(gaze_.sample(t()), stimulus.spec, frame, head ? &*head : nullptr);
      } else {
        eye_samples[0] = sanitize_gaze(gaze_.sample(t()), stimulus.spec.width_px, stimulus.spec.height_px,
                                       last_valid_gaze_ ? &*last_valid_gaze_ : nullptr);
        if (eye_samples[0].valid) last_valid_gaze_ = eye_samples[0];
      }
      const GazeSample& sample = eye_samples[0];
      // Image `frame * refreshes + refresh` of this presentation, its position in the logged arrays:
      // a gaze-dependent stimulus (fipr) renders it now with this refresh's gaze (replay does the same).
      const StimulusImage image{frame, frame * refreshes + refresh, sample, head};
      const PreparedFrame& shown = library_.frame(stimulus_id, stimulus.spec, image);
      double shown_at = 0.0;
      if (!right_eye_) {
        shown_at =
            time_base_s_ + (shown.on_device ? presenter_.present(shown.on_device) : presenter_.present(shown.image));
      } else {
        const GazeSample& right_sample = eye_samples[1];
        const PreparedFrame& right = right_eye_->library->frame(
            stimulus_id, stimulus.spec, StimulusImage{image.frame, image.image_index, right_sample, head});
        std::array<ViewFrame, 2> eyes{ViewFrame{&shown.image, shown.on_device, {}},
                                      ViewFrame{&right.image, right.on_device, {}}};
        if (head && right_eye_->eyes_in_world) {
          const std::array<ViewPose, 2> rendered_from = right_eye_->eyes_in_world(*head);
          for (size_t eye = 0; eye < 2; ++eye) eyes[eye].rendered_from = rendered_from[eye];
        }
        shown_at = time_base_s_ + presenter_.present_views(eyes);
        right_hashes.push_back(right_eye_->library->hash(right));
        right_gaze.push_back({right_sample.x_px, right_sample.y_px});
        if (!right_sample.valid)
          event.right_eye_invalid_gaze.push_back(
              {static_cast<int>(event.present_s.size()), right_sample.invalid_reason});
      }
      if (previous >= 0) {
        const long periods = std::lround((shown_at - previous) * presenter_.refresh_hz());
        if (periods > 1) dropped += static_cast<int>(periods - 1);
      }
      previous = shown_at;
      if (const std::optional<bool> frame_late = presenter_.last_frame_late())
        late = late.value_or(0) + (*frame_late ? 1 : 0);
      if (!sample.valid)
        event.invalid_gaze.push_back({static_cast<int>(event.present_s.size()), sample.invalid_reason});
      event.present_s.push_back(shown_at);
      event.frame.push_back(frame);
      event.hash.push_back(library_.hash(shown));  // a live frame's: read back now, after its present
      if (frame == 0 && refresh == refreshes - 1 && wants_screenshot("stimulus"))
        save_screenshot("stimulus", shown.image);
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
  if (right_eye_) {
    event.right_eye_hash = std::move(right_hashes);
    event.right_eye_gaze = std::move(right_gaze);
  }
  if (right_eye_ && right_eye_->head_pose) event.head_pose = std::move(head_poses);
  event.late_frames = late;
  log(to_json(event));
  dropped_frames_ += dropped;
  if (late) late_frames_ = late_frames_.value_or(0) + *late;
}

std::array<GazeSample, 2> SessionRun::headset_gaze(const GazeSample& raw, const StimulusSpec& spec, int frame,
                                                   const HeadPose* head) {
  const HeadsetGazeGeometry& geometry = right_eye_->gaze_geometry;
  // The scene's surface along a ray of the head now: traced from where the head is (head-tracked), the
  // distance along the ray the same in either head's axes.
  const auto surface_distance = [&](const std::array<double, 3>& origin, const std::array<double, 3>& direction) {
    if (!head) return library_.surface_distance(spec, frame, origin, direction);
    return library_.surface_distance(spec, frame, point_in_start_head(*head, origin),
                                     direction_in_start_head(*head, direction));
  };
  const bool on_depth = right_eye_->gaze_fixation == GazeFixation::rendered_depth;
  const int width_px = spec.width_px, height_px = spec.height_px;
  GazeSample left_raw = raw;
  std::optional<GazeSample> right_raw;
  if (on_depth && raw.ray_in_head && (raw.valid || raw.invalid_reason == "off_screen")) {
    // The eye tracker's ray, resting on the surface it meets: both eyes' pixels come from that point
    // (the source's own pixel was the ray's direction at infinity). Off the left image at infinity
    // may be on it at the surface, so its "off_screen" is decided again here.
    GazeSample ray_template = raw;
    ray_template.valid = true;
    ray_template.invalid_reason.clear();
    const GazeRay& ray = *raw.ray_in_head;
    // A ray that is none (not finite, no direction) is traced nowhere: eye_gaze_from_ray_at_depth
    // makes it "not_finite".
    const auto finite = [](const std::array<double, 3>& v) {
      return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
    };
    const bool traceable = finite(ray.origin_m) && finite(ray.direction) &&
                           (ray.direction[0] != 0.0 || ray.direction[1] != 0.0 || ray.direction[2] != 0.0);
    const std::optional<double> distance =
        traceable ? surface_distance(ray.origin_m, ray.direction) : std::nullopt;
    const auto rested = eye_gaze_from_ray_at_depth(geometry, ray.origin_m, ray.direction, distance, ray_template);
    left_raw = rested[0];
    right_raw = rested[1];
  }
  const GazeSample left =
      sanitize_gaze(left_raw, width_px, height_px, last_valid_gaze_ ? &*last_valid_gaze_ : nullptr);
  if (left.valid) last_valid_gaze_ = left;
  // The right eye's pixel of the same gaze, from the left's as used (rounded; an invalid left gives
  // an invalid right, which holds the right eye's last position), rounded and substituted as the left's.
  if (!left.valid) {
    right_raw = left;
  } else if (!right_raw && on_depth) {
    const std::optional<GazeRay> ray = left_eye_ray_of_pixel(geometry, left.x_px, left.y_px);
    const std::optional<double> distance =
        ray ? surface_distance(ray->origin_m, ray->direction) : std::nullopt;
    right_raw = eye_gaze_from_left_eye_pixel_at_depth(geometry, left, distance)[1];
  } else if (!right_raw) {
    right_raw = eye_gaze_from_left_eye_pixel(geometry, left)[1];
  }
  const GazeSample right =
      sanitize_gaze(*right_raw, width_px, height_px, last_valid_right_gaze_ ? &*last_valid_right_gaze_ : nullptr);
  if (right.valid) last_valid_right_gaze_ = right;
  return {left, right};
}

void SessionRun::validate_tracker(const char* reason) {
  const ValidationConfig& validation = plan_.config.validation;
  if (!validation.enabled) return;
  const DisplayConfig& display = plan_.config.display;
  const DisplayGeometry geometry = display_geometry(display);
  const std::vector<std::pair<double, double>> targets = validation_targets_px(display, validation);
  const double radius_px = validation_target_radius_px(display, validation);
  const double period_s = 1.0 / presenter_.refresh_hz();
  // Each target is held for the refreshes that fit in target_s, and measured from the first
  // refresh at or after settle_s (0.2 s at 60 Hz: refreshes 12 to the last).
  const int refreshes = static_cast<int>(std::floor(validation.target_s * presenter_.refresh_hz() + 1e-9));
  const int first_measured = static_cast<int>(std::ceil(validation.settle_s * presenter_.refresh_hz() - 1e-9));
  std::string message = "Eye-tracker check: look at the dark dot in the middle of each disk until the disk moves.";
  for (int attempt = 1; attempt <= validation.max_attempts; ++attempt) {
    show_text(message + "\n\nPress an answer key to start.", attempt == 1 ? "validation" : "validation_retry");
    wait_for_key();
    TrackerValidationEvent event;
    event.reason = reason;
    event.attempt = attempt;
    event.start_s = t();
    // The centre (index 4 of 9, 2 of 5) first; the rest in an order the participant cannot learn,
    // seeded by the session and this attempt's start (the log lists the targets as shown).
    std::vector<size_t> order;
    const size_t centre = targets.size() / 2;
    for (size_t i = 0; i < targets.size(); ++i)
      if (i != centre) order.push_back(i);
    Pcg32 random(derive_seed(derive_seed(plan_.session_seed, "validation"), std::bit_cast<uint64_t>(event.start_s)));
    random.shuffle(order);
    order.insert(order.begin(), centre);
    try {
      for (const size_t index : order) {
        const auto [x_px, y_px] = targets[index];
        const FixationTargetScope looking(gaze_, x_px, y_px);
        if (right_eye_) {
          show_validation_target_in_both_eyes(x_px, y_px, radius_px);
        } else {
          show_screen("validation_target", [&] {
            return validation_target_frame(display.width_px, display.height_px, x_px, y_px, radius_px);
          });
        }
        const double shown_s = presenter_.now_s();
        std::vector<GazeSample> samples;
        for (int refresh = 1; refresh <= refreshes; ++refresh) {
          presenter_.wait_until(shown_s + refresh * period_s);
          if (presenter_.close_requested()) throw SessionAborted{presenter_.close_reason()};
          if (refresh >= first_measured) samples.push_back(gaze_.sample(t()));
        }
        event.targets.push_back(measure_validation_target(geometry, x_px, y_px, samples));
      }
    } catch (const SessionAborted&) {
      // Stopped mid-attempt: what was measured is logged all the same, marked stopped.
      event.stopped = true;
      summarise_validation(event, validation);
      log(to_json(event));
      throw;
    }
    summarise_validation(event, validation);
    log(to_json(event));
    const std::string result = "accuracy " + degrees_text(event.accuracy_deg) + " (at most " +
                               format_number(validation.max_accuracy_deg, 3) + "), precision " +
                               degrees_text(event.precision_deg) + " (at most " +
                               format_number(validation.max_precision_deg, 3) + ")";
    std::fprintf(stderr, "fovlab: eye-tracker validation (%s, attempt %d of %d): %s: %s\n", reason, attempt,
                 validation.max_attempts, result.c_str(), event.passed ? "passed" : "not passed");
    if (event.passed) return;
    message = "The eye-tracker check did not pass (attempt " + std::to_string(attempt) + " of " +
              std::to_string(validation.max_attempts) + "): " + result +
              ".\n\nSit still, and look at the dot in the middle of each disk.";
  }
  throw SessionAborted{"the eye-tracker validation did not pass in " + std::to_string(validation.max_attempts) +
                       " attempts: recalibrate the tracker"};
}

void SessionRun::show_validation_target_in_both_eyes(double x_px, double y_px, double radius_px) {
  // The target is a point in front of the head that the left eye sees at (x_px, y_px): on the
  // fixation plane, or with rendered-depth (no surface is shown behind a target) at optical
  // infinity, the depth the eye tracker's samples rest at when their ray meets nothing. The right
  // eye sees it where that point appears to it, so the two eyes fuse one target at that depth.
  const HeadsetGazeGeometry& geometry = right_eye_->gaze_geometry;
  GazeSample left;
  left.x_px = x_px;
  left.y_px = y_px;
  const GazeSample right = right_eye_->gaze_fixation == GazeFixation::rendered_depth
                               ? eye_gaze_from_left_eye_pixel_at_depth(geometry, left, std::nullopt)[1]
                               : eye_gaze_from_left_eye_pixel(geometry, left)[1];
  const int width_px = plan_.config.display.width_px, height_px = plan_.config.display.height_px;
  const Rgba8Frame left_frame = validation_target_frame(width_px, height_px, x_px, y_px, radius_px);
  // A target the right eye cannot see (off its image) is shown to the left eye alone.
  const Rgba8Frame right_frame = right.valid
                                     ? validation_target_frame(width_px, height_px, right.x_px, right.y_px, radius_px)
                                     : black_frame(width_px, height_px);
  presenter_.present_views(std::array{ViewFrame{&left_frame, {}, {}}, ViewFrame{&right_frame, {}, {}}});
  save_screenshot("validation_target", left_frame);
  save_screenshot("validation_target_right_eye", right_frame);
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
  const std::optional<Answer> answer = responses_.await(request, presenter_, plan_.config.timing.response_timeout_s);
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

bool SessionRun::run_trials(int first, int attention_errors, bool resumed, int complete_before,
                            AdaptiveProgress& adaptive) {
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
  if (checks_on && attention_errors >= config.attention.max_errors) return exclude(excluded_logged_, complete_before);
  {
    show_text(resumed ? "The session resumes where it stopped.\n\n" + config.instructions : config.instructions,
              "instructions");
    const double onset_s = presenter_.now_s();
    wait_for_key();
    log(to_json(InstructionsEvent{{}, time_base_s_ + onset_s}));
  }
  // The eye-tracker validation due before the next trial: at the start of every run, after breaks.
  const char* validation_due = resumed ? TrackerValidationEvent::resumed : TrackerValidationEvent::start;
  bool first_of_run = true;  // the run's first trial presented (the one at `first` may be skipped)
  for (size_t index = static_cast<size_t>(first); index < plan_.trials.size(); ++index) {
    const Trial& planned = plan_.trials[index];
    const std::optional<Trial> presented = adaptive.presented(planned);
    if (!presented) continue;  // its adaptive track has stopped
    const Trial& trial = *presented;
    const PlannedBlock& block = plan_.blocks.at(static_cast<size_t>(trial.block));
    const bool block_starts = trial.index == block.first_trial || first_of_run;
    first_of_run = false;
    // No rest after the practice block: a screen that says the study begins instead.
    const bool after_practice = trial.block > 0 && plan_.blocks.at(static_cast<size_t>(trial.block - 1)).practice;
    if (trial.index == block.first_trial && after_practice) {
      show_text("The practice is over: the study begins now.\n\nPress an answer key to begin.", "practice_end");
      wait_for_key();
    }
    if (trial.index == block.first_trial && trial.block > 0 && !after_practice &&
        config.timing.rest_between_blocks_s > 0) {
      const double start = t();
      take_break("Rest before the next block.", config.timing.rest_between_blocks_s, "rest");
      log(to_json(BreakEvent{{}, BreakEvent::rest, std::nullopt, start, t() - start}));
      if (config.validation.after_breaks && !validation_due) validation_due = TrackerValidationEvent::rest;
    }
    if (validation_due) {
      validate_tracker(validation_due);
      validation_due = nullptr;
    }
    if (block_starts) log(to_json(BlockStartEvent{{}, trial.block, block.name, block.scene}));
    if (block.practice && trial.index == block.first_trial) {
      show_text("Practice: " + std::to_string(block.trial_count) +
                    " trials to learn the task. These answers are not "
                    "part of the results.\n\nPress an answer key to begin.",
                "practice");
      wait_for_key();
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
    start.practice = trial.practice;
    if (trial.track >= 0) start.track = trial.track;
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
        if (config.validation.after_breaks) validation_due = TrackerValidationEvent::after_break;
      }
    }
    log(to_json(TrialEndEvent{{}, trial.index}));
    adaptive.record(planned, answer);
    if (options_.trial_progress) options_.trial_progress(double(index + 1) / double(plan_.trials.size()));
    if (checks_on && attention_errors >= config.attention.max_errors)
      return exclude(false, complete_before + trials_completed_);
    show_black(config.timing.inter_trial_s);
  }
  show_text("Thank you. The session is complete.", "end");
  log(to_json(SessionEndEvent{{}, SessionEndEvent::completed, complete_before + trials_completed_}));
  return true;
}

}  // namespace fovlab

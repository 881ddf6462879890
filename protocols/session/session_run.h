#pragma once
// The state machine of one run of a session: instructions, then the plan's trials from a given
// index (block rests, stimuli, questions, attention checks and breaks), then the end; every step is
// logged as it happens. run_session (session.h) sets it up: plan, presenter, gaze, answers, log.
#include <array>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "protocols/gaze/gaze_source.h"
#include "protocols/gaze/headset_gaze.h"
#include "study/config/headset_display.h"
#include "study/log/event_log.h"
#include "display/presenter.h"
#include "study/schedule/adaptive_progress.h"
#include "study/schedule/study_plan.h"
#include "protocols/session/response_source.h"
#include "protocols/session/session.h"
#include "protocols/stimuli/stimulus_library.h"

namespace fovlab {

// The question screen's text: the question, a blank line, then the first key of each answer one
// a line ("S: same", "D: different"): the text screen wraps words and joins runs of spaces, so
// keys on one line ran together (issue 18).
std::string question_screen_text(const QuestionConfig& question);

// A headset session's right eye (the session's library renders the left): the library that renders
// each stimulus as the right eye sees it, the geometry that turns the gaze source's pixel (the
// left eye's) into the right eye's (protocols/session/headset_views.h), and where the gaze rests.
// With rendered-depth, each refresh's gaze ray (the eye tracker's, or the left eye's ray through a
// source's pixel) rests where it meets the stimulus's scene at that frame's time, traced by GT with
// the left eye's library's tracer (StimulusLibrary::surface_distance); both eyes' pixels are those
// of that point, or of the ray's direction at optical infinity where it meets nothing.
struct RightEyeStimuli {
  StimulusLibrary* library = nullptr;
  HeadsetGazeGeometry gaze_geometry;
  GazeFixation gaze_fixation = GazeFixation::fixation_distance;
  // Head-tracked views (empty: head-locked): the head's pose at the coming refresh's predicted display
  // time relative to the session's start (protocols/session/head_tracking.h), nullopt when the runtime
  // gives none. Each refresh renders both eyes from it, sanitized, and logs it (head_pose).
  std::function<std::optional<HeadPose>()> head_pose;
  // Head-tracked: where each eye's image of a refresh was rendered from, in the runtime's LOCAL space
  // (the head's reference pose carrying the eye as the refresh's head pose moved it), which the
  // headset's compositor is given with the image so that the scene stays fixed in the world.
  std::function<std::array<ViewPose, 2>(const HeadPose&)> eyes_in_world;
};

class SessionRun {
 public:
  // time_base_s: the session time at which this run starts (the last logged time when resuming).
  // right_eye: a headset session's (presenter.view_count() == 2), else nullptr.
  SessionRun(const StudyPlan& plan, const SessionOptions& options, Presenter& presenter, GazeSource& gaze,
             ResponseSource& responses, StimulusLibrary& library, EventLogWriter& log, double time_base_s,
             const RightEyeStimuli* right_eye = nullptr);

  // Session time now.
  double t() { return time_base_s_ + presenter_.now_s(); }
  // Appends an event, with "t" unless it has one.
  void log(nlohmann::json event);
  // Runs trials from `first` to the end (`complete_before` of them already in the log; `adaptive`:
  // the adaptive tracks' progress, each answer folded in as it is logged, a stopped track's trials
  // skipped); returns false when the participant was excluded (also when a resumed log already
  // holds max_errors wrong attention checks). Throws SessionAborted when the participant closes
  // the window.
  bool run_trials(int first, int attention_errors, bool resumed, int complete_before, AdaptiveProgress& adaptive);
  // The log being resumed already has its "excluded" event (a crash before session_end).
  void set_excluded_logged(bool logged) { excluded_logged_ = logged; }
  int events_written() const { return events_written_; }
  int trials_completed() const { return trials_completed_; }  // trial_end events of this run
  // Of this run's stimulus refreshes: the gaze sample's age at present time (those with a sample),
  // and the refresh periods missed.
  const std::vector<double>& gaze_age_s() const { return gaze_age_s_; }
  int dropped_frames() const { return dropped_frames_; }
  // Of this run's stimulus refreshes, those the presenter says were late (last_frame_late); nullopt
  // when it cannot tell.
  std::optional<int> late_frames() const { return late_frames_; }

 private:
  // A screen drawn by `draw` (only when it is shown or saved: a headless run without screenshots
  // draws nothing), presented in a window and saved as <screen_kind>.png when asked.
  void show_screen(const std::string& screen_kind, const std::function<Rgba8Frame()>& draw);
  void show_text(const std::string& text, const std::string& screen_kind);
  void show_black(double duration_s);
  // The fixation cross for `duration_s` (nothing when 0).
  void show_fixation(double duration_s);
  // A break of at least `duration_s`: the text with the seconds left, updated each second, then
  // "Press an answer key to continue." until one (the simulated observer after its usual 2 s).
  void take_break(const std::string& text, double duration_s, const std::string& screen_kind);
  // A screen held until an answer key (as the instructions are): the end of a break, the end of an
  // excluded participant's session.
  void wait_for_key();
  // With --screenshots, the first screen of each kind ("instructions", "fixation", "stimulus",
  // "question", "break", "break_end", "rest", "rest_end", "end", "excluded", "validation",
  // "validation_retry", "validation_target", "practice", "practice_end") is saved as <kind>.png:
  // the swapchain's image in a window, the frame itself when headless. `frame`: what is on screen (a headless run shows nothing).
  bool wants_screenshot(const std::string& kind) const;
  void save_screenshot(const std::string& kind, const Rgba8Frame& frame);
  // Shows every frame of a stimulus, each for its refreshes, with the gaze of each refresh; a
  // gaze-dependent stimulus renders one image a refresh, the presentation's images in order. In a
  // headset, each eye its own image, rendered from its view with its gaze.
  void present_stimulus(const Trial& trial, int step, int stimulus_id);
  // A headset's eye-tracker validation target, each eye shown the one point (docs/hmd.md).
  void show_validation_target_in_both_eyes(double x_px, double y_px, double radius_px);
  // A headset's gaze in each eye's image at one refresh, sanitized (rounded, invalid ones held):
  // the left eye's first. `raw`: the source's sample; `spec` and `frame`: what is shown (the scene
  // a rendered-depth gaze rests on).
  // `head`: a head-tracked refresh's head pose (the gaze ray in the head is traced in the scene from where
  // the head is); nullptr: head-locked.
  std::array<GazeSample, 2> headset_gaze(const GazeSample& raw, const StimulusSpec& spec, int frame,
                                         const HeadPose* head = nullptr);
  // The eye-tracker validation of [validation] (nothing without one): the targets one at a time,
  // the centre first, the others in a seeded order; attempts until one passes, each logged (a
  // tracker_validation event) and printed on stderr for the operator. After max_attempts failures
  // it throws SessionAborted: the session pauses, and resuming it validates again first.
  void validate_tracker(const char* reason);
  // Shows the question and waits for an answer; logs it. A timeout logs an answer of "" (missed).
  Answer ask(const Trial& trial, int step, int ladder_index);
  std::string run_comparison(const Trial& trial);  // returns the answer
  void run_ramp(const Trial& trial);
  void run_slider(const Trial& trial);

  const StudyPlan& plan_;
  const SessionOptions& options_;
  Presenter& presenter_;
  GazeSource& gaze_;
  ResponseSource& responses_;
  StimulusLibrary& library_;
  EventLogWriter& log_;
  double time_base_s_;
  const RightEyeStimuli* right_eye_;
  std::optional<GazeSample> last_valid_gaze_;
  std::optional<GazeSample> last_valid_right_gaze_;
  std::optional<HeadPose> last_head_pose_;  // head-tracked: the last pose rendered from
  std::set<std::string> screenshots_taken_;
  bool excluded_logged_ = false;
  int events_written_ = 0;
  int trials_completed_ = 0;
  std::vector<double> gaze_age_s_;
  int dropped_frames_ = 0;
  std::optional<int> late_frames_;
};

}  // namespace fovlab

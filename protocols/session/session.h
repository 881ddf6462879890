#pragma once
// A participant's session: a state machine over the study plan (instructions, blocks with rests,
// trials, end) that shows stimuli through a presenter, takes answers from a response source, and
// writes every event to the log the moment it happens (docs/log-schema.md). Running it again for a
// participant whose log exists resumes after the last complete trial.
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "study/config/study_config.h"

namespace fovlab {

struct SessionOptions {
  std::string participant;
  std::string results_dir = "results";
  std::string observer;                     // "" for a human at the keys, else "simulated[:k=v,...]"
  std::string gaze;                         // "" for the default: mouse in a window, synthetic headless
  std::string cache_dir = "stimuli/cache";  // the pre-render cache (path-traced frames, Voronoi masks)
  // The config's [participant] fields given on the command line (name -> value), and how to ask
  // for the others when a new session starts (empty: not asked; a human's missing field is then an
  // InputError, a simulated observer's is left empty). A resumed session keeps its header's.
  std::map<std::string, std::string> participant_fields;
  std::function<std::string(const std::string& name)> ask_participant_field;
  // Hears the share of the stimuli prepared (0 to 1) while they render before the first trial.
  std::function<void(double)> prepare_progress;
  // Hears the share of the schedule's trials done after each trial (a headless pilot runs for
  // minutes with nothing on screen).
  std::function<void(double)> trial_progress;
  bool headless = false;
  std::string device_selector;          // --device: renders (and, in a window, presents unless present_device_selector)
  std::string present_device_selector;  // --present-device: a window on another device (frames copied through the host)
  bool validation = false;
  std::string screenshots_dir;  // the first screen of each kind as <kind>.png (session_run.h), headless too
  std::string lab_key_path;     // --lab-key: key the log's seals (a file outside results_dir)
  // --new-version: a new participant under a config that differs from the sessions in
  // results/<study> runs in the folder of its version, results/<study>@vN (study/log/study_versions.h),
  // instead of being refused.
  bool new_version = false;
  // A headset session that loses the focus while its runtime still runs it pauses (session_paused,
  // the log sealed) and waits this long, in seconds of the session clock, for the focus to return
  // and resume in the same run; 0: it exits at once, as a closed window does (docs/hmd.md).
  double refocus_timeout_s = 600.0;
  // A headset session's mirror window on the desktop (--mirror-window): the left eye's image for the
  // operator, and the keyboard beside the controller (OpenXrPresenterOptions::mirror_window,
  // docs/hmd.md). Ignored by a window or headless session.
  bool mirror_window = false;
};

struct SessionOutcome {
  std::string
      study_folder;  // the study's folder under results_dir: "<study>", or "<study>@vN" for a later config version
  std::string log_path;
  int trials_completed = 0;  // complete trials in the log, this run and earlier ones
  int trials_total = 0;
  bool trials_total_is_upper_bound = false;  // adaptive tracks: one that stops early skips the rest of its trials
  int trials_run = 0;                        // complete trials added by this run
  bool resumed = false;
  bool excluded = false;
  bool finished = false;      // the session reached its end (all trials, or exclusion)
  std::string stop_reason;    // why it stopped early (window closed...)
  double plan_s = 0.0;        // building the schedule
  double prepare_s = 0.0;     // rendering stimuli before the first trial
  double trial_loop_s = 0.0;  // wall time from the first event of this run to its last
  double wall_s = 0.0;
  double log_write_s = 0.0;  // write + fsync of all events of this run
  int events_written = 0;
  // Gaze-to-present latency of this run: every stimulus refresh's gaze sample age at present time
  // (refreshes without a sample left out), the refresh periods missed, and the present clock.
  std::vector<double> gaze_age_s;
  int dropped_frames = 0;
  // A headset's stimulus refreshes whose xrEndFrame came after their predicted display time
  // (nullopt: not measured, a window or a runtime without XR_KHR_convert_timespec_time).
  std::optional<int> late_frames;
  int focus_pauses_resumed = 0;  // a headset's pauses for a lost focus that resumed in this run
  std::string present_clock;
  std::string frame_path;            // "on_device", "via_host", "none" (headless)
  int cross_device_frames = 0;       // via_host: frames copied from the rendering device to the presenting one
  double cross_device_copy_s = 0.0;  // and the seconds those copies took
};

// The log path of a participant: <results>/<study>/<participant>/events.jsonl.
std::string session_log_path(const std::string& results_dir, const std::string& study, const std::string& participant);

// "P001", "P002", ...: the first of these with no folder under <results>/<study>/ nor under any
// later version's <results>/<study>@vN/ (for `fovlab run --participant next`, so a demo or pilot
// can be started again and again, and an ID names one person across versions).
std::string next_participant_id(const std::string& results_dir, const std::string& study);

// Everything is checked before the first event is written: participant ID, results folder,
// an existing log (same study and config, not finished, intact), observer and gaze specs.
SessionOutcome run_session(const StudyConfig& config, const SessionOptions& options);

}  // namespace fovlab
